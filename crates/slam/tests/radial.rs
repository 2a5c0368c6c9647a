//! Radial-distance regressors (thesis §4.1.3) on synthetic data: each recovers a known
//! smooth function (R² > 0.95 on held-out points), 10-fold cross-validation picks order 3
//! for noisy data from a cubic, PCA finds a known principal axis, and trained models
//! survive a JSON round trip.

use rand::RngExt;
use rand_distr::{Distribution, Normal};
use whisker_slam::frontend::features::{ContactFeatures, Feature};
use whisker_slam::radial::RadialEstimator;
use whisker_slam::radial::cross_validation::r2;
use whisker_slam::radial::mlp::{Mlp, MlpTraining};
use whisker_slam::radial::pca::Pca;
use whisker_slam::radial::polynomial::Polynomial;
use whisker_slam::radial::svr::Svr;
use whisker_slam::rng::substream;

/// A smooth function of two inputs on very different scales (as the contact features
/// are): f = sin(x₁) + 0.5·(x₂/1000)².
fn smooth(n: usize, stream: &str) -> (Vec<Vec<f64>>, Vec<f64>) {
    let mut rng = substream(5, stream);
    let x: Vec<Vec<f64>> = (0..n)
        .map(|_| {
            vec![
                rng.random_range(-2.0..2.0),
                rng.random_range(-1500.0..1500.0),
            ]
        })
        .collect();
    let y = x
        .iter()
        .map(|r| r[0].sin() + 0.5 * (r[1] / 1000.0).powi(2))
        .collect();
    (x, y)
}

fn held_out_r2(predict: impl Fn(&[f64]) -> f64) -> f64 {
    let (x, y) = smooth(200, "test/radial/held-out");
    let p: Vec<f64> = x.iter().map(|r| predict(r)).collect();
    r2(&p, &y)
}

#[test]
fn each_regressor_recovers_a_smooth_function() {
    let (x, y) = smooth(300, "test/radial/train");
    let poly = Polynomial::fit(&x, &y, 5);
    let p = held_out_r2(|r| poly.predict(r));
    assert!(p > 0.95, "polynomial R² {p}");
    let mlp = Mlp::fit(&x, &y, &[12, 12], &MlpTraining::default());
    let m = held_out_r2(|r| mlp.predict(r));
    assert!(m > 0.95, "MLP R² {m}");
    let (svr, _) = Svr::fit_search(&x, &y, &Svr::default_grid(2), 5, 0).unwrap();
    let s = held_out_r2(|r| svr.predict(r));
    assert!(s > 0.95, "SVR R² {s}");
    println!(
        "held-out R²: polynomial(5) {p:.4}, MLP(12,12) {m:.4}, SVR {s:.4} ({:?})",
        svr.params
    );
}

#[test]
fn ten_fold_cross_validation_picks_order_3_for_a_noisy_cubic() {
    let mut rng = substream(6, "test/radial/cubic");
    let noise = Normal::new(0.0, 0.3).unwrap();
    let x: Vec<Vec<f64>> = (0..400)
        .map(|_| vec![rng.random_range(-2.0..2.0)])
        .collect();
    let y: Vec<f64> = x
        .iter()
        .map(|r| r[0].powi(3) - 2.0 * r[0] + 0.5 + noise.sample(&mut rng))
        .collect();
    let (model, scores) = Polynomial::fit_cv(&x, &y, 2..=6, 10, 0);
    println!("CV MSE by order: {scores:?}");
    assert_eq!(model.degree, 3, "{scores:?}");
    // Order 2 cannot follow a cubic: its CV error is far above the noise variance 0.09.
    assert!(scores[0].1.mean > 2.0 * scores[1].1.mean);
}

#[test]
fn pca_finds_the_direction_of_greatest_variance() {
    // Two standardised features that move together (y = x + small noise) and one
    // independent: the first component loads the pair equally, the third nothing else.
    let mut rng = substream(7, "test/radial/pca");
    let n = Normal::new(0.0, 1.0).unwrap();
    let x: Vec<Vec<f64>> = (0..2000)
        .map(|_| {
            let a = n.sample(&mut rng);
            vec![a, a + 0.1 * n.sample(&mut rng), n.sample(&mut rng)]
        })
        .collect();
    let pca = Pca::fit(&x);
    let c = &pca.components[0];
    let h = 0.5f64.sqrt();
    assert!(
        (c[0] - h).abs() < 0.01 && (c[1] - h).abs() < 0.01 && c[2].abs() < 0.05,
        "{c:?}"
    );
    assert!(pca.variances[0] > 1.9 && pca.variances[0] < 2.1);
    let w: Vec<Vec<f64>> = x.iter().map(|r| pca.whiten(r, 3)).collect();
    for k in 0..3 {
        let var = w.iter().map(|r| r[k] * r[k]).sum::<f64>() / w.len() as f64;
        assert!((var - 1.0).abs() < 1e-9, "component {k}: variance {var}");
    }
}

#[test]
fn estimators_round_trip_through_json_and_stay_within_the_whisker() {
    let (x, y) = smooth(120, "test/radial/json");
    let features = vec![Feature::Cp, Feature::Ca];
    let model = Svr::fit(&x, &y, Svr::default_grid(2)[4]).unwrap();
    let e = RadialEstimator::Svr { features, model };
    let text = serde_json::to_string(&e).unwrap();
    let back: RadialEstimator = serde_json::from_str(&text).unwrap();
    assert_eq!(back, e);
    let f = ContactFeatures {
        cp: 0.3,
        ca: 500.0,
        wl: 0.1,
        ..ContactFeatures::default()
    };
    let mut rng = substream(8, "test/radial/estimate");
    for est in [&back, &RadialEstimator::Tip, &RadialEstimator::Random] {
        let r = est.estimate(&f, &mut rng);
        assert!((0.0..=0.1).contains(&r));
    }
    assert_eq!(RadialEstimator::Tip.estimate(&f, &mut rng), 0.1);
}
