//! Slurm time limits (`--time`), parsed and checked before anything is written, so that a
//! typo fails at once instead of in the queue.

use std::fmt;

/// A job time limit, in seconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimeLimit {
    /// Whole seconds, > 0.
    pub seconds: u64,
}

impl fmt::Display for TimeLimit {
    /// Slurm's `days-hours:minutes:seconds`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self.seconds;
        let (days, hours, minutes, seconds) = (s / 86_400, s / 3600 % 24, s / 60 % 60, s % 60);
        write!(f, "{days}-{hours:02}:{minutes:02}:{seconds:02}")
    }
}

/// The formats sbatch takes, for messages.
pub const TIME_FORMATS: &str = "minutes, minutes:seconds, hours:minutes:seconds, days-hours, \
                                days-hours:minutes or days-hours:minutes:seconds";

impl std::str::FromStr for TimeLimit {
    type Err = String;

    /// Parses the formats of sbatch's `--time`: `M`, `M:S`, `H:M:S`, `D-H`, `D-H:M` and
    /// `D-H:M:S`. Seconds and minutes after a colon must be below 60, hours after a day
    /// below 24; the limit must be positive (Slurm's 0, "no limit", is refused: a case that
    /// hangs should not hold a node for ever).
    fn from_str(text: &str) -> Result<Self, String> {
        let bad =
            |why: String| format!("time limit '{text}': {why}; the formats are {TIME_FORMATS}");
        let number = |part: &str, what: &str| -> Result<u64, String> {
            if part.is_empty() || !part.bytes().all(|b| b.is_ascii_digit()) {
                return Err(bad(format!("{what} '{part}' is not a whole number")));
            }
            part.parse::<u64>()
                .map_err(|_| bad(format!("{what} '{part}' is too large")))
        };
        let below = |value: u64, limit: u64, what: &str| -> Result<u64, String> {
            if value < limit {
                Ok(value)
            } else {
                Err(bad(format!("{what} {value} must be below {limit}")))
            }
        };
        let (days, clock) = match text.split_once('-') {
            Some((d, rest)) => (Some(number(d, "days")?), rest),
            None => (None, text),
        };
        let parts: Vec<&str> = clock.split(':').collect();
        let seconds = match (days, parts.as_slice()) {
            (None, [m]) => number(m, "minutes")? * 60,
            (None, [m, s]) => {
                number(m, "minutes")? * 60 + below(number(s, "seconds")?, 60, "seconds")?
            }
            (None, [h, m, s]) => {
                number(h, "hours")? * 3600
                    + below(number(m, "minutes")?, 60, "minutes")? * 60
                    + below(number(s, "seconds")?, 60, "seconds")?
            }
            (Some(d), [h]) => d * 86_400 + below(number(h, "hours")?, 24, "hours")? * 3600,
            (Some(d), [h, m]) => {
                d * 86_400
                    + below(number(h, "hours")?, 24, "hours")? * 3600
                    + below(number(m, "minutes")?, 60, "minutes")? * 60
            }
            (Some(d), [h, m, s]) => {
                d * 86_400
                    + below(number(h, "hours")?, 24, "hours")? * 3600
                    + below(number(m, "minutes")?, 60, "minutes")? * 60
                    + below(number(s, "seconds")?, 60, "seconds")?
            }
            _ => return Err(bad("too many fields".into())),
        };
        if seconds == 0 {
            return Err(bad("it must be positive".into()));
        }
        Ok(TimeLimit { seconds })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<u64, String> {
        text.parse::<TimeLimit>().map(|t| t.seconds)
    }

    #[test]
    fn every_sbatch_format_is_read() {
        assert_eq!(parse("90"), Ok(5400));
        assert_eq!(parse("25:30"), Ok(25 * 60 + 30));
        assert_eq!(parse("48:00:00"), Ok(48 * 3600));
        assert_eq!(parse("2-12"), Ok(2 * 86_400 + 12 * 3600));
        assert_eq!(parse("1-02:03"), Ok(86_400 + 2 * 3600 + 180));
        assert_eq!(parse("1-02:03:04"), Ok(86_400 + 2 * 3600 + 184));
        // Written back in the longest form, which reads back to the same limit.
        let limit: TimeLimit = "1-02:03:04".parse().unwrap();
        assert_eq!(limit.to_string(), "1-02:03:04");
        assert_eq!(parse(&limit.to_string()), Ok(limit.seconds));
    }

    #[test]
    fn malformed_limits_name_the_field_and_the_formats() {
        for (text, needle) in [
            ("25:99", "seconds 99 must be below 60"),
            ("1:75:00", "minutes 75 must be below 60"),
            ("1-24", "hours 24 must be below 24"),
            ("", "minutes '' is not a whole number"),
            ("ten", "minutes 'ten' is not a whole number"),
            ("1:2:3:4", "too many fields"),
            ("-5", "days '' is not a whole number"),
            ("0", "must be positive"),
            ("0:00:00", "must be positive"),
            ("99999999999999999999", "too large"),
        ] {
            let err = parse(text).unwrap_err();
            assert!(err.contains(needle), "{text}: {err}");
            assert!(err.contains(&format!("'{text}'")), "{text}: {err}");
            assert!(err.contains("days-hours:minutes:seconds"), "{err}");
        }
    }
}
