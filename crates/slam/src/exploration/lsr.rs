//! Least similar region, LSR (thesis §6.1.2.3, Eq 6.1–6.3, Fig 6.3): to resolve an
//! ambiguity, go to the mapped region least like the one under the array now, by the
//! cheapest path through the experience graph.
//!
//! - Rows (Eq 6.1–6.2): for every experience i ≠ n of a likely object, [χ²(f_n, f_i),
//!   NMSE(s_n, s_i)] against the current observation o_n; sorted by χ², then NMSE,
//!   descending. The first row is the least similar; every experience whose row ties it
//!   exactly carries "its feature" (E_smin).
//! - Graph: experiences are nodes, links are edges travelled either way; the cost of
//!   stepping onto node b is w = w_t + w_r + 1/n_l (Eq 6.3), with w_t the translation and
//!   w_r the rotation angle between the two experiences' map poses and n_l the number of
//!   links to and from b. Units (`shared/notes/chapter6.md` §10.10): metres and radians
//!   by default (SI), each with a scale.
//! - Target: of E_smin, the one the cheapest path reaches (petgraph's Dijkstra); if none
//!   is reachable from the current experience (maps of different objects are not linked,
//!   §5.2.2.2), the next group of sorted rows.

use crate::features::similarity::{Features, chi2, nmse};
use crate::whisker_ratslam::object_map::ObjectMap;
use petgraph::algo::{astar, dijkstra};
use petgraph::graph::{DiGraph, NodeIndex};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Weights of Eq 6.3's terms.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LsrParams {
    /// Cost per metre of translation between map poses (1: SI, as MATLAB would have).
    pub translation_per_m: f64,
    /// Cost per radian of rotation between map poses (1).
    pub rotation_per_rad: f64,
}

impl Default for LsrParams {
    fn default() -> Self {
        Self {
            translation_per_m: 1.0,
            rotation_per_rad: 1.0,
        }
    }
}

/// One row of S (Eq 6.1–6.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// The experience compared.
    pub experience: usize,
    /// χ² of the point feature histograms.
    pub chi2: f64,
    /// NMSE of the slope distribution arrays.
    pub nmse: f64,
}

/// The rows of every experience except `current` whose object `likely` accepts, least
/// similar first (χ² descending, then NMSE descending, then experience id).
pub fn rows(
    map: &ObjectMap,
    seen: &Features,
    current: usize,
    likely: impl Fn(Option<&str>) -> bool,
) -> Vec<Row> {
    let mut rows: Vec<Row> = map
        .experiences
        .iter()
        .filter(|e| e.id != current && likely(e.object.as_deref()))
        .map(|e| Row {
            experience: e.id,
            chi2: chi2(&seen.pfh, &e.features.pfh),
            nmse: nmse(&seen.sda.filled(), &e.features.sda.filled()),
        })
        .collect();
    rows.sort_by(|a, b| {
        b.chi2
            .total_cmp(&a.chi2)
            .then(b.nmse.total_cmp(&a.nmse))
            .then(a.experience.cmp(&b.experience))
    });
    rows
}

/// The experience graph with Eq 6.3's costs on its edges.
pub struct ExperienceGraph {
    graph: DiGraph<usize, f64>,
}

impl ExperienceGraph {
    /// The graph of `map`'s experiences and links.
    pub fn new(map: &ObjectMap, params: &LsrParams) -> Self {
        let n = map.experiences.len();
        let mut graph = DiGraph::with_capacity(n, 2 * map.links.len());
        for id in 0..n {
            graph.add_node(id);
        }
        let mut degree = vec![0usize; n];
        for l in map.links.iter().filter(|l| l.from != l.to) {
            degree[l.from] += 1;
            degree[l.to] += 1;
        }
        for l in map.links.iter().filter(|l| l.from != l.to) {
            let (a, b) = (map.pose(l.from), map.pose(l.to));
            let (wt, wr) = crate::pose::distance(&a, &b);
            let w = params.translation_per_m * wt + params.rotation_per_rad * wr;
            graph.add_edge(
                NodeIndex::new(l.from),
                NodeIndex::new(l.to),
                w + 1.0 / degree[l.to] as f64,
            );
            graph.add_edge(
                NodeIndex::new(l.to),
                NodeIndex::new(l.from),
                w + 1.0 / degree[l.from] as f64,
            );
        }
        Self { graph }
    }

    /// A graph from explicit directed edges (from, to, cost) over `nodes` nodes.
    pub fn from_edges(nodes: usize, edges: &[(usize, usize, f64)]) -> Self {
        let mut graph = DiGraph::with_capacity(nodes, edges.len());
        for id in 0..nodes {
            graph.add_node(id);
        }
        for &(a, b, w) in edges {
            graph.add_edge(NodeIndex::new(a), NodeIndex::new(b), w);
        }
        Self { graph }
    }

    /// The cost of the cheapest path from `from` to every node it reaches.
    pub fn costs(&self, from: usize) -> BTreeMap<usize, f64> {
        dijkstra(&self.graph, NodeIndex::new(from), None, |e| *e.weight())
            .into_iter()
            .map(|(n, c)| (n.index(), c))
            .collect()
    }

    /// The cheapest path from `from` to `to` (both ends included) and its cost.
    pub fn path(&self, from: usize, to: usize) -> Option<(f64, Vec<usize>)> {
        let goal = NodeIndex::new(to);
        astar(
            &self.graph,
            NodeIndex::new(from),
            |n| n == goal,
            |e| *e.weight(),
            |_| 0.0,
        )
        .map(|(c, p)| (c, p.into_iter().map(NodeIndex::index).collect()))
    }
}

/// Where LSR sends the array.
#[derive(Debug, Clone, PartialEq)]
pub struct LsrPlan {
    /// The least similar reachable experience.
    pub target: usize,
    /// The path to it, from the current experience (included) to the target.
    pub path: Vec<usize>,
    /// The path's cost (Eq 6.3 summed).
    pub cost: f64,
    /// The target's row.
    pub row: Row,
}

/// LSR's plan from the `current` experience for observation `seen`, over experiences of
/// objects `likely` accepts; None when no such experience is reachable.
pub fn plan(
    map: &ObjectMap,
    seen: &Features,
    current: usize,
    likely: impl Fn(Option<&str>) -> bool,
    params: &LsrParams,
) -> Option<LsrPlan> {
    let rows = rows(map, seen, current, likely);
    let graph = ExperienceGraph::new(map, params);
    let costs = graph.costs(current);
    let mut start = 0;
    while start < rows.len() {
        let head = rows[start];
        let end = start
            + rows[start..]
                .iter()
                .take_while(|r| r.chi2 == head.chi2 && r.nmse == head.nmse)
                .count();
        let best = rows[start..end]
            .iter()
            .filter_map(|r| costs.get(&r.experience).map(|&c| (c, *r)))
            .min_by(|a, b| {
                a.0.total_cmp(&b.0)
                    .then(a.1.experience.cmp(&b.1.experience))
            });
        if let Some((cost, row)) = best {
            let (_, path) = graph.path(current, row.experience).expect("reachable");
            return Some(LsrPlan {
                target: row.experience,
                path,
                cost,
                row,
            });
        }
        start = end;
    }
    None
}
