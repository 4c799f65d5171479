//! Analysis of results: signals (spectra, oscillation counts) and derived quantities.

pub mod signal;
