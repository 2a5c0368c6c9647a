//! Named, reproducible random sub-streams of a scenario seed.
//!
//! Every stochastic part of the system (sensor noise of one whisker, odometry noise,
//! IK restarts, a trial's object placement…) asks for its own generator with
//! [`substream`]`(seed, name)`. The stream depends only on the seed and the stable name,
//! so results are byte-identical whatever the number of threads or the order in which
//! parts are created, and adding noise to one part never shifts the draws of another.
//!
//! The generator is Xoshiro256++ (`rand_xoshiro`), seeded through SplitMix64 from a
//! 64-bit FNV-1a hash of the name mixed with the seed. Both the hash and the seeding are
//! fixed algorithms written here, so a stream never changes with a dependency update of
//! the hashing in `std`.

use rand::SeedableRng;
pub use rand_xoshiro::Xoshiro256PlusPlus as StreamRng;

/// 64-bit FNV-1a hash of a byte string (stable across platforms and releases).
fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// SplitMix64 finaliser: a bijective avalanche mix of 64 bits.
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The 64-bit key of the sub-stream `name` of `seed`.
pub fn substream_key(seed: u64, name: &str) -> u64 {
    splitmix64(splitmix64(seed) ^ fnv1a64(name.as_bytes()))
}

/// A generator for the part called `name` of the experiment seeded with `seed`.
///
/// Names are hierarchical by convention, with `/` separators, e.g.
/// `"sensor/whisker/07"` or `"odometry"`.
pub fn substream(seed: u64, name: &str) -> StreamRng {
    StreamRng::seed_from_u64(substream_key(seed, name))
}

/// A draw from N(0, σ); exactly 0, without a draw, when σ = 0 (a noise switched off
/// consumes nothing from the stream).
pub fn gauss<R: rand::Rng + ?Sized>(sigma: f64, rng: &mut R) -> f64 {
    use rand_distr::{Distribution, Normal};
    if sigma == 0.0 {
        0.0
    } else {
        Normal::new(0.0, sigma)
            .expect("a finite, non-negative sigma")
            .sample(rng)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::RngExt;

    fn draws(seed: u64, name: &str, n: usize) -> Vec<f64> {
        let mut r = substream(seed, name);
        (0..n).map(|_| r.random::<f64>()).collect()
    }

    #[test]
    fn same_seed_and_name_give_the_same_stream() {
        assert_eq!(draws(7, "odometry", 100), draws(7, "odometry", 100));
    }

    #[test]
    fn a_stream_does_not_depend_on_other_streams_being_drawn() {
        let alone = draws(3, "sensor/whisker/00", 50);
        let mut other = substream(3, "sensor/whisker/01");
        let _: Vec<f64> = (0..1000).map(|_| other.random::<f64>()).collect();
        assert_eq!(alone, draws(3, "sensor/whisker/00", 50));
    }

    /// Streams of different names (or seeds) are distinct and uncorrelated: the sample
    /// correlation of 20,000 paired uniforms has standard error 1/sqrt(n) ≈ 0.007.
    #[test]
    fn different_names_and_seeds_are_uncorrelated() {
        let n = 20_000;
        let pairs = [
            (draws(1, "a", n), draws(1, "b", n)),
            (draws(1, "a", n), draws(2, "a", n)),
            (
                draws(0, "sensor/whisker/00", n),
                draws(0, "sensor/whisker/01", n),
            ),
        ];
        for (x, y) in &pairs {
            assert_ne!(x[..4], y[..4]);
            let mx = x.iter().sum::<f64>() / n as f64;
            let my = y.iter().sum::<f64>() / n as f64;
            let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
            for (a, b) in x.iter().zip(y) {
                sxy += (a - mx) * (b - my);
                sxx += (a - mx) * (a - mx);
                syy += (b - my) * (b - my);
            }
            let corr = sxy / (sxx * syy).sqrt();
            assert!(corr.abs() < 4.0 / (n as f64).sqrt(), "correlation {corr}");
            assert!((mx - 0.5).abs() < 4.0 * (1.0 / 12.0f64 / n as f64).sqrt());
        }
    }

    #[test]
    fn keys_of_close_names_differ_in_about_half_their_bits() {
        let a = substream_key(0, "sensor/whisker/00");
        let b = substream_key(0, "sensor/whisker/01");
        let flipped = (a ^ b).count_ones();
        assert!((16..=48).contains(&flipped), "{flipped} bits differ");
    }
}
