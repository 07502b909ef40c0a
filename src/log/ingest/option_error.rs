//! A read option written as text (on a command line, in a recipe, in the workbench's fields)
//! that does not read as one: which option, what was written, and what is accepted.

/// A read option's text that cannot be read; the variant names the option.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OptionError {
    /// `rate_unit`: no rate unit the reader knows.
    #[error("unknown rate unit \"{0}\": use deg/h (dph), deg/s (dps), mdeg/s (mdps) or rad/s")]
    RateUnit(String),
    /// `time_unit`: no time unit the reader knows.
    #[error("unknown time unit \"{0}\": use s, ms, us, ns, min, h or samples")]
    TimeUnit(String),
    /// `time_col`, `rate_col` or `temp_col`: empty.
    #[error("empty column reference: give a column name or a 1-based number")]
    EmptyColumn,
    /// `delimiter`: not a separator the reader takes.
    #[error(
        "unknown delimiter \"{0}\": use a single character such as , or ;, \\t (tab) or space \
         (runs of blanks)"
    )]
    Delimiter(String),
}
