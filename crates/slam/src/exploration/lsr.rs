//! Least similar region, LSR (thesis §6.1.2.3, Eq 6.1–6.3, Fig 6.3): to resolve an
//! ambiguity, go to the mapped region least like the one under the array now, by the
//! cheapest path through the experience graph.
//!
//! - Scope ([`Scope`]): the likely objects' maps — their own experiences and the links
//!   they were loaded with. Experiences and links the run makes are not "the entire set of
//!   possible objects" (§6.1.2.3), and a link the run makes between two loaded maps (one
//!   whisk re-localising into each) would join maps that are unlinked by construction
//!   (§5.2.2.2).
//! - Rows (Eq 6.1–6.2): for every in-scope experience other than the current one and the
//!   start nodes, [χ²(f_n, f_i), NMSE(s_n, s_i)] against the current observation o_n;
//!   sorted by χ², then NMSE, descending. The first row is the least similar; every
//!   experience whose row ties it exactly carries "its feature" (E_smin).
//! - Start nodes: each likely map's last re-localised experience — the array's last known
//!   place in that map (maps of different objects are not linked, so a path into a map
//!   starts from its own last re-localisation; our reading of §6.1.2.3).
//! - Graph: experiences are nodes, links are edges travelled either way; the cost of
//!   stepping onto node b is w = w_t + w_r + 1/n_l (Eq 6.3), with w_t the translation and
//!   w_r the rotation angle between the two experiences' map poses and n_l the number of
//!   in-scope links to and from b. Units ([`CostScale`]): by default each term is divided
//!   by its mean over the scope's edges, so that a typical link costs 1 + 1 + 1 — in metres
//!   and radians (SI) 1/n_l dominates (a 2 cm, 10° link costs 0.02 + 0.17 against 0.1–0.5)
//!   and paths through hubs are nearly free whatever their length; in cm and degrees the
//!   rotation would. `scale = "weights"` uses fixed per-metre and per-radian weights.
//! - Target: of E_smin, the one the cheapest path reaches (petgraph's Dijkstra) from its
//!   map's start node; if none is reachable, the next group of sorted rows.

use crate::features::similarity::{Features, chi2, nmse};
use crate::whisker_ratslam::object_map::ObjectMap;
use petgraph::algo::{astar, dijkstra};
use petgraph::graph::{DiGraph, NodeIndex};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The units of Eq 6.3's w_t and w_r.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum CostScale {
    /// Each of the three terms in units of its mean over the scope's edges.
    #[default]
    LinkMean,
    /// w_t × `translation_per_m` + w_r × `rotation_per_rad` + 1/n_l.
    Weights,
}

/// When LSR plans a new target (§6.1.2.1, §6.1.2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Replan {
    /// On every re-localisation into a likely map, as FEH (§6.1.2.1: both strategies
    /// monitor re-localisations), besides the two cases below.
    #[default]
    Relocalisation,
    /// Only when another object takes the lead (§6.1.2.3's wording) or the target is
    /// reached.
    Leader,
}

/// LSR's parameters (`[explore.lsr]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LsrParams {
    /// Units of Eq 6.3's terms.
    pub scale: CostScale,
    /// With `scale = "weights"`: cost per metre of translation between map poses (1: SI).
    pub translation_per_m: f64,
    /// With `scale = "weights"`: cost per radian of rotation between map poses (1).
    pub rotation_per_rad: f64,
    /// When a new target is planned.
    pub replan: Replan,
}

impl Default for LsrParams {
    fn default() -> Self {
        Self {
            scale: CostScale::LinkMean,
            translation_per_m: 1.0,
            rotation_per_rad: 1.0,
            replan: Replan::Relocalisation,
        }
    }
}

/// The part of a map LSR searches: the likely objects' maps as they were loaded.
#[derive(Debug, Clone, Copy)]
pub struct Scope<'a> {
    /// The likely objects: an experience is in scope when recorded on one of them.
    pub objects: &'a [String],
    /// The links the maps were loaded with are `links[..own_links]`; later ones are the
    /// run's.
    pub own_links: usize,
    /// The start nodes: each likely map's last re-localised experience.
    pub starts: &'a [usize],
}

impl Scope<'_> {
    /// Whether experience `id` of `map` is in scope.
    pub fn holds(&self, map: &ObjectMap, id: usize) -> bool {
        map.experiences[id]
            .object
            .as_deref()
            .is_some_and(|o| self.objects.iter().any(|l| l == o))
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

/// The rows of every in-scope experience except `current` and the start nodes, least
/// similar first (χ² descending, then NMSE descending, then experience id).
pub fn rows(map: &ObjectMap, seen: &Features, current: usize, scope: &Scope) -> Vec<Row> {
    let mut rows: Vec<Row> = map
        .experiences
        .iter()
        .filter(|e| e.id != current && !scope.starts.contains(&e.id) && scope.holds(map, e.id))
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
    /// The graph of the in-scope experiences of `map` and the links they were loaded with.
    pub fn new(map: &ObjectMap, scope: &Scope, params: &LsrParams) -> Self {
        let n = map.experiences.len();
        let links: Vec<(usize, usize)> = map.links[..scope.own_links.min(map.links.len())]
            .iter()
            .filter(|l| l.from != l.to && scope.holds(map, l.from) && scope.holds(map, l.to))
            .map(|l| (l.from, l.to))
            .collect();
        let mut degree = vec![0usize; n];
        for &(a, b) in &links {
            degree[a] += 1;
            degree[b] += 1;
        }
        // Each link both ways: (from, to, w_t, w_r, 1/n_l of `to`).
        let terms: Vec<(usize, usize, f64, f64, f64)> = links
            .iter()
            .flat_map(|&(a, b)| {
                let (wt, wr) = crate::pose::distance(&map.pose(a), &map.pose(b));
                [
                    (a, b, wt, wr, 1.0 / degree[b] as f64),
                    (b, a, wt, wr, 1.0 / degree[a] as f64),
                ]
            })
            .collect();
        let [kt, kr, kn] = match params.scale {
            CostScale::Weights => [params.translation_per_m, params.rotation_per_rad, 1.0],
            CostScale::LinkMean => {
                let per_mean = |f: fn(&(usize, usize, f64, f64, f64)) -> f64| {
                    let mean = terms.iter().map(f).sum::<f64>() / terms.len().max(1) as f64;
                    if mean > 0.0 { 1.0 / mean } else { 0.0 }
                };
                [per_mean(|t| t.2), per_mean(|t| t.3), per_mean(|t| t.4)]
            }
        };
        let edges: Vec<(usize, usize, f64)> = terms
            .iter()
            .map(|&(a, b, wt, wr, nl)| (a, b, kt * wt + kr * wr + kn * nl))
            .collect();
        Self::from_edges(n, &edges)
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
    /// The path to it, from its map's start node (included) to the target.
    pub path: Vec<usize>,
    /// The path's cost (Eq 6.3 summed).
    pub cost: f64,
    /// The target's row.
    pub row: Row,
    /// How many experiences share the target's row (|E_smin|, when the first group is
    /// reachable).
    pub tied: usize,
    /// Rows ahead of the target's group (less like the observation than it) passed over
    /// because no start node reaches them.
    pub skipped: usize,
}

/// LSR's plan for observation `seen` made at experience `current`, over `scope`; None when
/// no in-scope experience is reachable from a start node.
pub fn plan(
    map: &ObjectMap,
    seen: &Features,
    current: usize,
    scope: &Scope,
    params: &LsrParams,
) -> Option<LsrPlan> {
    let rows = rows(map, seen, current, scope);
    let graph = ExperienceGraph::new(map, scope, params);
    // The cheapest cost to each node from any start node, and that start.
    let mut best: BTreeMap<usize, (f64, usize)> = BTreeMap::new();
    for &s in scope.starts {
        for (node, c) in graph.costs(s) {
            let e = best.entry(node).or_insert((c, s));
            if c < e.0 {
                *e = (c, s);
            }
        }
    }
    let mut start = 0;
    while start < rows.len() {
        let head = rows[start];
        let end = start
            + rows[start..]
                .iter()
                .take_while(|r| r.chi2 == head.chi2 && r.nmse == head.nmse)
                .count();
        let reachable = rows[start..end]
            .iter()
            .filter_map(|r| best.get(&r.experience).map(|&(c, s)| (c, s, *r)));
        if let Some((cost, from, row)) = reachable.min_by(|a, b| {
            a.0.total_cmp(&b.0)
                .then(a.2.experience.cmp(&b.2.experience))
        }) {
            let (_, path) = graph.path(from, row.experience)?;
            return Some(LsrPlan {
                target: row.experience,
                path,
                cost,
                row,
                tied: end - start,
                skipped: start,
            });
        }
        start = end;
    }
    None
}
