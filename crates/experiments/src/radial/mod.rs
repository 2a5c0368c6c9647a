//! `whisker radial`: the radial-distance experiments of thesis Chapter 4 — physics data
//! sets ([`generate`]), the twelve regressors of Table 4.1 ([`train`]) and their
//! validation against the tip assumption and a random guess ([`eval`], Figs 4.8–4.9).

pub mod eval;
pub mod generate;
pub mod train;

use std::path::Path;
use whisker_scenario::{Error, Result};
use whisker_slam::frontend::features::Feature;
use whisker_slam::radial::dataset::{RadialSample, from_csv};
use whisker_slam::radial::table_4_1_features;

/// A model label of Table 4.1: nn1–nn4, poly5–poly8, svr9–svr12.
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    /// The label, e.g. "svr10".
    pub name: String,
    /// "nn", "poly" or "svr".
    pub family: &'static str,
    /// Its input features.
    pub features: Vec<Feature>,
}

impl Label {
    /// The label `name`, or an input error listing the valid ones.
    pub fn parse(name: &str) -> Result<Self> {
        let split = name
            .find(|c: char| c.is_ascii_digit())
            .unwrap_or(name.len());
        let (family, number) = name.split_at(split);
        let range = match family {
            "nn" => 1..=4,
            "poly" => 5..=8,
            "svr" => 9..=12,
            _ => 0..=0,
        };
        match number.parse::<usize>() {
            Ok(k) if range.contains(&k) && k > 0 => Ok(Self {
                name: name.to_string(),
                family: match family {
                    "nn" => "nn",
                    "poly" => "poly",
                    _ => "svr",
                },
                features: table_4_1_features(k),
            }),
            _ => Err(Error::Input(format!(
                "unknown model `{name}`: expected one of nn1–nn4, poly5–poly8, svr9–svr12 (Table 4.1)"
            ))),
        }
    }

    /// The twelve labels in Table 4.1's order.
    pub fn all() -> Vec<Self> {
        let names = (1..=12).map(|k| match k {
            1..=4 => format!("nn{k}"),
            5..=8 => format!("poly{k}"),
            _ => format!("svr{k}"),
        });
        names.map(|n| Self::parse(&n).expect("Table 4.1")).collect()
    }

    /// `names`, or all twelve if empty.
    pub fn parse_list(names: &[String]) -> Result<Vec<Self>> {
        if names.is_empty() {
            Ok(Self::all())
        } else {
            names.iter().map(|n| Self::parse(n)).collect()
        }
    }

    /// Its features as in Table 4.1, e.g. "CP-CA-DV-DA-AV".
    pub fn feature_names(&self) -> String {
        feature_names(&self.features)
    }
}

/// Feature names joined as in Table 4.1.
pub fn feature_names(features: &[Feature]) -> String {
    features
        .iter()
        .map(|f| format!("{f:?}").to_uppercase())
        .collect::<Vec<_>>()
        .join("-")
}

/// Reads a data set; a malformed file is an input error naming it, the line and column.
pub fn read_set(path: &Path) -> Result<Vec<RadialSample>> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::Input(format!("{}: cannot read the data set: {e}", path.display())))?;
    from_csv(&text).map_err(|e| Error::Input(format!("{}: {e}", path.display())))
}
