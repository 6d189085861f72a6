//! The crate's one error type.

use std::path::PathBuf;

use crate::units::Seconds;

/// Everything that can go wrong in the plant: a bad robot config, a bad input, a bad request.
///
/// Config messages name the key (as `section.key`, the way it is written in the TOML file)
/// and say what to write instead.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The config file could not be read.
    #[error("cannot read robot config `{path}`: {source}")]
    ReadConfig {
        /// The file asked for.
        path: PathBuf,
        /// Why it could not be read.
        #[source]
        source: std::io::Error,
    },

    /// The config is not valid TOML, misses a key, has a value of the wrong type or a key this
    /// crate does not know (the message from the TOML parser names it and its line).
    #[error(
        "robot config does not parse (fix the key it names; every key is listed in \
         fixtures/robots/henrytwo-ideal.toml): {}",
        one_line(.0)
    )]
    ParseConfig(#[from] toml::de::Error),

    /// A number that must be finite is `nan` or `inf`.
    #[error("robot config `{key}` is {value}: {allowed} (nan and inf are not allowed)")]
    NotFinite {
        /// The key, as `section.key`.
        key: String,
        /// The value read.
        value: f64,
        /// The allowed range, in words.
        allowed: String,
    },

    /// A number outside the physical range of its key (a battery of 1e6 V, a gear ratio of
    /// 1e-6, a time constant of a picosecond; nan and inf too).
    #[error("{key} = {value}: {allowed} ({meaning})")]
    Unphysical {
        /// The key, as `section.key`.
        key: String,
        /// The value read, as written in the message.
        value: String,
        /// The range, "give 1e-5 to 10 s".
        allowed: String,
        /// What the key is.
        meaning: &'static str,
    },

    /// A config file that does not validate: the file, then what is wrong in it.
    #[error("{}: {error}", path.display())]
    InFile {
        /// The file.
        path: PathBuf,
        /// What is wrong (not a `source`: the message already says it).
        error: Box<Error>,
    },

    /// A duty is outside `[0, 1]`.
    #[error(
        "robot config `{key}` = {value}: a duty must lie in [0, 1] \
         (an 8-bit PWM compare value divided by 255, e.g. 210/255 = 0.8235)"
    )]
    DutyOutOfRange {
        /// The key, as `section.key`.
        key: String,
        /// The value read.
        value: f64,
    },

    /// The dead band reaches the reference duty, so the motor would not turn where its gain
    /// is defined.
    #[error(
        "robot config `{dead_band_key}` = {dead_band} must be below `{reference_key}` = \
         {reference}: the motor has to turn at the duty where its gain was measured"
    )]
    DeadBandNotBelowReference {
        /// The dead-band key, as `section.key`.
        dead_band_key: String,
        /// Its value.
        dead_band: f64,
        /// The reference-duty key, as `section.key`.
        reference_key: String,
        /// Its value.
        reference: f64,
    },

    /// A value is outside the range its key allows (a fraction above 1, a negative
    /// length, a ratio far from 1, an empty battery above a full one...).
    #[error("robot config `{key}` = {value}: {allowed} ({meaning})")]
    OutOfRange {
        /// The key, as `section.key`.
        key: String,
        /// The value read.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
        /// What the key is, to help choose a value.
        meaning: &'static str,
    },

    /// Two keys set the same thing.
    #[error("robot config sets both `{key}` and `{other}`: {why}")]
    Conflict {
        /// One key, as `section.key`.
        key: String,
        /// The other key.
        other: String,
        /// Which one to keep.
        why: &'static str,
    },

    /// A fault or override given at run time has a value that makes no sense.
    #[error("{what} = {value}: {allowed}")]
    InvalidFault {
        /// The fault parameter.
        what: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },

    /// A duty given at run time is outside `[0, 1]` or not finite.
    #[error("duty {value} is outside [0, 1]: scale the PWM compare value to its period first")]
    InvalidDuty {
        /// The fraction given.
        value: f64,
    },

    /// `advance_to` was asked to go back in time (or to a time that is not a number). The plant
    /// is left as it was.
    #[error("cannot advance the plant to {requested}: it is already at {now}, and time only moves forward")]
    TimeWentBackwards {
        /// The plant time.
        now: Seconds,
        /// The time asked for.
        requested: Seconds,
    },
}

/// The TOML parser's message on one line: where ("TOML parse error at line 3, column 1"),
/// the line it quotes, and what is wrong, without the carets it draws below the line.
fn one_line(e: &toml::de::Error) -> String {
    let text = e.to_string();
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let what = e.message().trim().replace('\n', "; ");
    let Some(first) = lines.first().filter(|f| f.starts_with("TOML parse error")) else {
        return what;
    };
    // The quoted source line is drawn as `24 | voltage_v = "7.4"`.
    let quoted = lines.iter().find_map(|l| {
        let (number, rest) = l.split_once(" | ")?;
        number.trim().parse::<usize>().ok().map(|_| rest.trim())
    });
    match quoted {
        Some(q) => format!("{first} (`{q}`): {what}"),
        None => format!("{first}: {what}"),
    }
}
