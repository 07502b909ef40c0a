//! The models: a fitted model's shared face (`fitted`), the named presets and model choices
//! (`presets`), the recipe of signal settings every model reads (`recipe`), Vakhrameev's
//! K0/K1±/K2± model (`vakhrameev`), the regression models of the other papers (`regression`),
//! and the curve approximations they are built from (`approx`).

pub mod approx;
pub mod fitted;
pub mod presets;
pub mod recipe;
pub mod regression;
pub mod vakhrameev;
