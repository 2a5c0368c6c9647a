//! Moving-average smoothing of the 2 kHz streams (thesis §5.1.1.1.1, §4.1.2.4: span 100
//! samples), with the semantics of Matlab's `smooth`: a centred window of odd span (an
//! even span is reduced by one), shrunk symmetrically near the ends so that it stays
//! centred (1, 3, 5, … samples at the first and last points).

/// The centred moving average of `x` over `span` samples.
pub fn moving_average(x: &[f64], span: usize) -> Vec<f64> {
    let n = x.len();
    let span = if span.is_multiple_of(2) {
        span.saturating_sub(1)
    } else {
        span
    }
    .max(1);
    let h = span / 2;
    let mut prefix = Vec::with_capacity(n + 1);
    prefix.push(0.0);
    for v in x {
        prefix.push(prefix.last().copied().unwrap_or(0.0) + v);
    }
    (0..n)
        .map(|i| {
            let r = h.min(i).min(n - 1 - i);
            (prefix[i + r + 1] - prefix[i - r]) / (2 * r + 1) as f64
        })
        .collect()
}

/// Central-difference derivative of `x` sampled at `rate` Hz (one-sided at the ends).
pub fn derivative(x: &[f64], rate: f64) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|i| match (i, n) {
            (_, 0 | 1) => 0.0,
            (0, _) => (x[1] - x[0]) * rate,
            (i, n) if i == n - 1 => (x[i] - x[i - 1]) * rate,
            (i, _) => (x[i + 1] - x[i - 1]) * rate / 2.0,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matlab_smooth_semantics() {
        // Span 4 acts as 3; the ends use 1 and 3 samples.
        let x = [1.0, 2.0, 6.0, 4.0, 10.0];
        let y = moving_average(&x, 4);
        assert_eq!(y, vec![1.0, 3.0, 4.0, 20.0 / 3.0, 10.0]);
        // A line is left unchanged by a centred window.
        let line: Vec<f64> = (0..300).map(|i| 3.0 * i as f64 - 7.0).collect();
        for (a, b) in moving_average(&line, 100).iter().zip(&line) {
            assert!((a - b).abs() < 1e-9);
        }
        // The derivative of a line sampled at 2 kHz is its slope × 2000.
        for d in derivative(&line, 2000.0) {
            assert!((d - 6000.0).abs() < 1e-9);
        }
    }
}
