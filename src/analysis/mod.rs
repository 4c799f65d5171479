//! Analysis of results: signals (spectra, oscillation counts), their spectral components
//! and derived quantities.

pub mod components;
pub mod kalker;
pub mod reference_curve;
pub mod richardson;
pub mod signal;
pub mod trace;

pub use components::{
    fixed_frequency_per_turn, spectral_components, Component, ComponentKind, ComponentOptions,
};
