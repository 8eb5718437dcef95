//! The bench's small pieces of arithmetic: order statistics of frame times and the date
//! of a run.

use serde::Serialize;

use crate::compare::metrics::nearest_rank;

/// Median and 95th percentile of a set of times.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Summary {
    pub median: f64,
    pub p95: f64,
}

impl Summary {
    /// The median (mean of the two middle values for an even count) and the nearest-rank
    /// 95th percentile (the smallest value with at least 95% of the values at or below it);
    /// NaN for no values.
    pub fn of(values: &[f64]) -> Self {
        if values.is_empty() {
            return Self {
                median: f64::NAN,
                p95: f64::NAN,
            };
        }
        let mut sorted = values.to_vec();
        sorted.sort_unstable_by(f64::total_cmp);
        let n = sorted.len();
        let median = if n % 2 == 1 {
            sorted[n / 2]
        } else {
            0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
        };
        Self {
            median,
            p95: nearest_rank(&sorted, 0.95),
        }
    }
}

/// `seconds` since the Unix epoch as an ISO 8601 UTC time, `2026-12-01T21:17:18Z`
/// (Hinnant's civil-from-days: the proleptic Gregorian calendar, no leap seconds).
pub fn utc_iso8601(seconds: u64) -> String {
    let days = (seconds / 86_400) as i64;
    let time = seconds % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era = (day_of_era - day_of_era / 1_460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_index = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * month_index + 2) / 5 + 1;
    let month = if month_index < 10 {
        month_index + 3
    } else {
        month_index - 9
    };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        time / 3600,
        time / 60 % 60,
        time % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts_and_nearest_rank_p95() {
        assert_eq!(Summary::of(&[3.0, 1.0, 2.0]).median, 2.0);
        assert_eq!(Summary::of(&[4.0, 1.0, 3.0, 2.0]).median, 2.5);
        // 1..=100: the 95th value is 95; 1..=20: ceil(19) = the 19th value.
        let hundred: Vec<f64> = (1..=100).rev().map(f64::from).collect();
        assert_eq!(
            Summary::of(&hundred),
            Summary {
                median: 50.5,
                p95: 95.0
            }
        );
        let twenty: Vec<f64> = (1..=20).map(f64::from).collect();
        assert_eq!(Summary::of(&twenty).p95, 19.0);
        assert_eq!(Summary::of(&[7.0]), Summary { median: 7.0, p95: 7.0 });
        assert!(Summary::of(&[]).median.is_nan());
    }

    #[test]
    fn utc_dates_across_leap_years_and_month_ends() {
        assert_eq!(utc_iso8601(0), "1970-01-01T00:00:00Z");
        assert_eq!(utc_iso8601(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(utc_iso8601(1_798_761_438), "2026-12-31T23:57:18Z");
    }
}
