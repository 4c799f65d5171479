//! Models built from bodies ([`crate::bodies`]): the scenarios whose model is more than one
//! body.
//!
//! - [`wheel_on_block`]: the paper's wheel, in its rotating frame, pressed onto and rolling
//!   along an elastic block (a second body, translating under the wheel) through a contact
//!   search.

pub mod wheel_on_block;
