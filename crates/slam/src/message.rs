//! How numbers are written in the messages of refused input.

/// `v` as people write it: plain between 0.001 and 100,000, in e-notation otherwise
/// (`1e308` rather than 309 digits).
pub fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-3..1e5).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn plain_in_the_middle_e_notation_at_the_ends() {
        let cases = [
            (20.0, "20"),
            (0.001, "0.001"),
            (-1e308, "-1e308"),
            (1e-320, "1e-320"),
            (2.5e9, "2.5e9"),
            (f64::NAN, "NaN"),
        ];
        for (v, want) in cases {
            assert_eq!(super::short(v), want);
        }
    }
}
