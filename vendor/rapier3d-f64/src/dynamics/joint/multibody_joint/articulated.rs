// Added by whisker-slam (vendor/PATCHES.md, patch 6): not part of Rapier 0.36.1.
//! The articulated-body factorisation of a multibody's augmented mass matrices: O(n) in
//! the DoFs instead of the dense O(n³) LU.
//!
//! Both matrices that `Multibody::update_mass_matrix` assembles have the form
//! `H = Σ_i G_iᵀ E_i G_i + Δ` over links `i`, where
//! - `G_i` (`D × n`) maps the generalised velocities to the link's state `y_i = G_i·q̇`:
//!   for the plain matrix (`D = 6`) its body Jacobian `J_i`; for the semi-implicit one
//!   (`D = 12`) the Jacobian stacked over the link's Coriolis rows `[J_i; C_i]`;
//! - `E_i` (`6 × D`) is the link's mass: `M_i` (plain) or `[M̃_i, dt·M_i]` (semi-implicit,
//!   `M̃_i` with `dt·` the gyroscopic derivative), so only a force (6 rows) comes out;
//! - `Δ` is diagonal: `dt·damping + armature + dt²·stiffness` per DoF;
//! - the state follows the tree: `y_i = Φ_i·y_parent + Ψ_i·q̇_i`, where `Ψ_i` (`D × nd`) is
//!   the link's own columns of `G_i` and `Φ_i` the shift from the parent's centre of mass
//!   to the link's (below).
//!
//! `Φ_i`, in 3 × 3 blocks of `[v; ω; c_v; c_ω]`, is
//! ```text
//! [ I  A  0  0 ]
//! [ 0  I  0  0 ]
//! [ 0  B  I  A ]
//! [ 0  C  0  I ]
//! ```
//! with `A = [r]×ᵀ` for the lever arm `r` (the first 6 × 6 block, `X_i`, is the plain
//! shift) and `B`, `C` the Coriolis rows' dependence on the parent's angular Jacobian.
//!
//! Gaussian elimination from the tips (Featherstone's articulated-body inertias,
//! generalised to the non-symmetric semi-implicit matrix): the force a link's subtree
//! exerts is affine in the link's state, `f_i = Ê_i·y_i + p_i`, with
//! `Ê_i = E_i + Σ_c X_cᵀ(Ê_c − K_c·D_c⁻¹·L_c)·Φ_c` over its children, `K = Ê·Ψ`,
//! `L = Sᵀ·Ê` (`S` = the upper 6 rows of `Ψ`) and the pivot `D = L·Ψ + Δ_i` (`nd × nd`).
//! The equations of link `i`'s DoFs, `Sᵀf_i + Δ_i·q̇_i = b_i`, give
//! `q̇_i = D⁻¹(b_i − Sᵀp_i − L·Φ_i·y_parent)`, solved root first. A force has no Coriolis
//! part (`E`'s lower rows are zero) and `Φ`'s Coriolis columns only reach Coriolis rows, so
//! `Ê` keeps zero lower rows: it is stored `6 × D`, and a force shifts by `X_iᵀ` alone.
//!
//! A joint's DoFs are padded to 6: the unused columns of `Ψ` are zero and `D` gets 1 on
//! its unused diagonal, so the padded unknowns solve to 0.

use crate::alloc_prelude::*;
use crate::math::Real;
use na::{Matrix3, SMatrix, SVector};

/// Joint DoFs are padded to this many.
pub(crate) const PAD: usize = 6;

/// One link's inputs: where it hangs and its terms of `H`.
#[derive(Clone, Debug)]
pub(crate) struct ArticulatedLink<const D: usize> {
    /// The parent's index (links are parents first), `None` for the root.
    pub parent: Option<usize>,
    /// The first of the link's DoFs in the generalised coordinates.
    pub first_dof: usize,
    /// The link's joint DoFs (≤ 6).
    pub ndofs: usize,
    /// `Φ`'s block `A` (the lever arm).
    pub a: Matrix3<Real>,
    /// `Φ`'s block `B` (unused when `D = 6`).
    pub b: Matrix3<Real>,
    /// `Φ`'s block `C` (unused when `D = 6`).
    pub c: Matrix3<Real>,
    /// The link's own columns of `G` (padded).
    pub psi: SMatrix<Real, D, PAD>,
    /// The link's mass `E` (`6 × D`).
    pub e: SMatrix<Real, 6, D>,
}

impl<const D: usize> ArticulatedLink<D> {
    /// `Φ·y`.
    fn shift(&self, y: &SVector<Real, D>) -> SVector<Real, D> {
        let mut out = *y;
        let w = y.fixed_rows::<3>(3).into_owned();
        let v = y.fixed_rows::<3>(0) + self.a * w;
        out.fixed_rows_mut::<3>(0).copy_from(&v);
        if D == 12 {
            let cw = y.fixed_rows::<3>(9).into_owned();
            let cv = y.fixed_rows::<3>(6) + self.b * w + self.a * cw;
            out.fixed_rows_mut::<3>(6).copy_from(&cv);
            out.fixed_rows_mut::<3>(9).copy_from(&(cw + self.c * w));
        }
        out
    }

    /// `Xᵀ·f` for a force.
    fn shift_force(&self, f: &SVector<Real, 6>) -> SVector<Real, 6> {
        let mut out = *f;
        let t = f.fixed_rows::<3>(3) + self.a.tr_mul(&f.fixed_rows::<3>(0));
        out.fixed_rows_mut::<3>(3).copy_from(&t);
        out
    }

    /// `Y·Φ` for `Y` (`R × D`): column block 1 gets `Y0·A` (and `Y2·B + Y3·C`), block 3
    /// gets `Y2·A`.
    fn right_shift<const R: usize>(&self, y: &SMatrix<Real, R, D>) -> SMatrix<Real, R, D> {
        let mut z = *y;
        let mut z1 = y.fixed_columns::<3>(0) * self.a + y.fixed_columns::<3>(3);
        if D == 12 {
            z1 += y.fixed_columns::<3>(6) * self.b + y.fixed_columns::<3>(9) * self.c;
            let z3 = y.fixed_columns::<3>(6) * self.a + y.fixed_columns::<3>(9);
            z.fixed_columns_mut::<3>(9).copy_from(&z3);
        }
        z.fixed_columns_mut::<3>(3).copy_from(&z1);
        z
    }

    /// `Xᵀ·Y·Φ`.
    fn congruence(&self, y: &SMatrix<Real, 6, D>) -> SMatrix<Real, 6, D> {
        let mut z = self.right_shift(y);
        let r1 = z.fixed_rows::<3>(3) + self.a.tr_mul(&z.fixed_rows::<3>(0));
        z.fixed_rows_mut::<3>(3).copy_from(&r1);
        z
    }

    /// `S`, the upper 6 rows of `Ψ`.
    fn s(&self) -> SMatrix<Real, 6, PAD> {
        self.psi.fixed_rows::<6>(0).into_owned()
    }

    /// The link's entries of `a`, padded.
    fn own(&self, a: &[Real]) -> SVector<Real, PAD> {
        let mut x = SVector::<Real, PAD>::zeros();
        for j in 0..self.ndofs {
            x[j] = a[self.first_dof + j];
        }
        x
    }
}

/// A slice indexed as a vector.
struct SliceIndex<'a>(&'a mut [Real]);

impl core::ops::Index<usize> for SliceIndex<'_> {
    type Output = Real;
    fn index(&self, i: usize) -> &Real {
        &self.0[i]
    }
}

impl core::ops::IndexMut<usize> for SliceIndex<'_> {
    fn index_mut(&mut self, i: usize) -> &mut Real {
        &mut self.0[i]
    }
}

/// One link's factor.
#[derive(Clone, Debug)]
struct LinkFactor<const D: usize> {
    /// `K·D⁻¹` (`6 × nd`).
    k_dinv: SMatrix<Real, 6, PAD>,
    /// `D⁻¹` (`nd × nd`).
    dinv: SMatrix<Real, PAD, PAD>,
    /// `D⁻¹·L·Φ` (`nd × D`).
    dinv_l_phi: SMatrix<Real, PAD, D>,
}

/// The factorised matrix `H` of a tree of links (module doc).
#[derive(Clone, Debug, Default)]
pub(crate) struct ArticulatedFactor<const D: usize> {
    links: Vec<ArticulatedLink<D>>,
    factors: Vec<LinkFactor<D>>,
    /// `Δ` per DoF.
    delta: Vec<Real>,
    /// `H⁻¹`'s columns for the root's DoFs, in DoF order, computed on the first
    /// [`Self::solve_root_mut`] that needs them (whisker-slam patch 10: a root driven by
    /// forces, with no weld, never does).
    root_response: std::sync::OnceLock<Vec<Real>>,
}

impl<const D: usize> LinkFactor<D> {
    /// Eliminates a link whose joint has `ND` DoFs (`ND = PAD` also serves the odd sizes,
    /// padded): its factor and the reduced `Ê − K·D⁻¹·L` its parent receives. `None` when
    /// the pivot block is singular.
    fn eliminate<const ND: usize>(
        link: &ArticulatedLink<D>,
        e_hat: &SMatrix<Real, 6, D>,
        delta: &[Real],
    ) -> Option<(Self, SMatrix<Real, 6, D>)> {
        let psi = link.psi.fixed_columns::<ND>(0).into_owned();
        let s = psi.fixed_rows::<6>(0).into_owned();
        let k = e_hat * psi;
        let l = s.tr_mul(e_hat);
        let mut d = l * psi;
        for j in 0..ND {
            if j < link.ndofs {
                d[(j, j)] += delta[link.first_dof + j];
            } else {
                d[(j, j)] = 1.0;
            }
        }
        let dinv = d.try_inverse()?;
        let k_dinv = k * dinv;
        let mut factor = LinkFactor::<D> {
            k_dinv: SMatrix::<Real, 6, PAD>::zeros(),
            dinv: SMatrix::<Real, PAD, PAD>::zeros(),
            dinv_l_phi: SMatrix::<Real, PAD, D>::zeros(),
        };
        factor.k_dinv.fixed_columns_mut::<ND>(0).copy_from(&k_dinv);
        factor.dinv.fixed_view_mut::<ND, ND>(0, 0).copy_from(&dinv);
        if link.parent.is_some() {
            let dinv_l_phi: SMatrix<Real, ND, D> = dinv * link.right_shift(&l);
            factor
                .dinv_l_phi
                .fixed_rows_mut::<ND>(0)
                .copy_from(&dinv_l_phi);
        }
        Some((factor, e_hat - k_dinv * l))
    }

    /// The up pass at a link of `ND` DoFs: `b_i ← u_i = b_i − Sᵀp_i`, and the bias force
    /// `Xᵀ(p_i + K·D⁻¹·u_i)` its parent receives.
    fn up<const ND: usize>(
        &self,
        link: &ArticulatedLink<D>,
        p: &SVector<Real, 6>,
        b: &mut impl core::ops::IndexMut<usize, Output = Real>,
    ) -> SVector<Real, 6> {
        let sp = link.psi.fixed_view::<6, ND>(0, 0).tr_mul(p);
        let mut u = SVector::<Real, ND>::zeros();
        for j in 0..link.ndofs.min(ND) {
            let v = b[link.first_dof + j] - sp[j];
            b[link.first_dof + j] = v;
            u[j] = v;
        }
        link.shift_force(&(p + self.k_dinv.fixed_columns::<ND>(0) * u))
    }

    /// The down pass at a link of `ND` DoFs: `b_i ← x_i` from `u_i` and the parent's state
    /// `y_p` (zero at the root), and the link's state.
    fn down<const ND: usize>(
        &self,
        link: &ArticulatedLink<D>,
        yp: Option<&SVector<Real, D>>,
        b: &mut impl core::ops::IndexMut<usize, Output = Real>,
    ) -> SVector<Real, D> {
        let mut u = SVector::<Real, ND>::zeros();
        for j in 0..link.ndofs.min(ND) {
            u[j] = b[link.first_dof + j];
        }
        let mut x = self.dinv.fixed_view::<ND, ND>(0, 0) * u;
        if let Some(yp) = yp {
            x -= self.dinv_l_phi.fixed_rows::<ND>(0) * yp;
        }
        for j in 0..link.ndofs.min(ND) {
            b[link.first_dof + j] = x[j];
        }
        let own = link.psi.fixed_columns::<ND>(0) * x;
        match yp {
            Some(yp) => link.shift(yp) + own,
            None => own,
        }
    }
}

impl<const D: usize> ArticulatedFactor<D> {
    /// Factorises `H` from its links (parents first) and its diagonal `Δ`. `None` when a
    /// joint's pivot block is singular.
    pub fn new(links: Vec<ArticulatedLink<D>>, delta: Vec<Real>) -> Option<Self> {
        let mut acc: Vec<SMatrix<Real, 6, D>> = links.iter().map(|l| l.e).collect();
        let mut factors = Vec::with_capacity(links.len());
        for i in (0..links.len()).rev() {
            let link = &links[i];
            // Spherical joints (3) and free roots (6) at their own size; others padded.
            let (factor, reduced) = match link.ndofs {
                1 => LinkFactor::eliminate::<1>(link, &acc[i], &delta)?,
                3 => LinkFactor::eliminate::<3>(link, &acc[i], &delta)?,
                _ => LinkFactor::eliminate::<PAD>(link, &acc[i], &delta)?,
            };
            if let Some(parent) = link.parent {
                acc[parent] += link.congruence(&reduced);
            }
            factors.push(factor);
        }
        factors.reverse();
        Some(Self {
            links,
            factors,
            delta,
            root_response: std::sync::OnceLock::new(),
        })
    }

    /// `H⁻¹`'s columns for the root's DoFs (one solve each), so that a row acting on the
    /// root alone (e.g. a weld of the root to another body, rebuilt every substep) is
    /// solved by [`Self::solve_root_mut`] in one pass over them.
    fn root_columns(&self) -> Vec<Real> {
        let n = self.delta.len();
        let root_dofs = self.links.first().map_or(0, |l| l.ndofs);
        let mut response = vec![0.0; n * root_dofs];
        for (j, column) in response.chunks_mut(n).enumerate() {
            column[j] = 1.0;
            self.solve_mut(&mut SliceIndex(column));
        }
        response
    }

    /// Solves `H·x = b` in place when `b` is zero outside the root's DoFs, from `H⁻¹`'s
    /// root columns (computed on the first call for this factorisation); `false` (nothing
    /// done) otherwise.
    pub fn solve_root_mut(&self, b: &mut impl core::ops::IndexMut<usize, Output = Real>) -> bool {
        let n = self.delta.len();
        let Some(root) = self.links.first() else {
            return false;
        };
        if (root.ndofs..n).any(|k| b[k] != 0.0) {
            return false;
        }
        let root_response = self.root_response.get_or_init(|| self.root_columns());
        let mut coefficients = [0.0; PAD];
        for (j, c) in coefficients.iter_mut().enumerate().take(root.ndofs) {
            *c = b[j];
        }
        for k in 0..n {
            b[k] = 0.0;
        }
        for (j, column) in root_response.chunks(n).enumerate() {
            let c = coefficients[j];
            if c != 0.0 {
                for k in 0..n {
                    b[k] += c * column[k];
                }
            }
        }
        true
    }

    /// Solves `H·x = b` in place (`b` indexed by DoF; any stride).
    pub fn solve_mut(&self, b: &mut impl core::ops::IndexMut<usize, Output = Real>) {
        let n = self.links.len();
        // Up pass: the bias forces p (upper 6 of each buffer), b_i becomes u_i = b_i − Sᵀp_i.
        let mut work = vec![SVector::<Real, D>::zeros(); n];
        for i in (0..n).rev() {
            let (link, f) = (&self.links[i], &self.factors[i]);
            let p = work[i].fixed_rows::<6>(0).into_owned();
            let up = match link.ndofs {
                1 => f.up::<1>(link, &p, b),
                3 => f.up::<3>(link, &p, b),
                _ => f.up::<PAD>(link, &p, b),
            };
            if let Some(parent) = link.parent {
                let mut pp = work[parent].fixed_rows_mut::<6>(0);
                pp += up;
            }
        }
        // Down pass: the states y, in the same buffer (a link's p is spent before its y).
        for i in 0..n {
            let (link, f) = (&self.links[i], &self.factors[i]);
            let yp = link.parent.map(|p| work[p]);
            work[i] = match link.ndofs {
                1 => f.down::<1>(link, yp.as_ref(), b),
                3 => f.down::<3>(link, yp.as_ref(), b),
                _ => f.down::<PAD>(link, yp.as_ref(), b),
            };
        }
    }

    /// `H·a` (`a` indexed by DoF): one pass down for the states, one up for the forces.
    pub fn mul(&self, a: &[Real]) -> Vec<Real> {
        let n = self.links.len();
        let mut states = vec![SVector::<Real, D>::zeros(); n];
        for i in 0..n {
            let link = &self.links[i];
            let x = link.own(a);
            states[i] = match link.parent {
                Some(parent) => link.shift(&states[parent]) + link.psi * x,
                None => link.psi * x,
            };
        }
        let mut forces = vec![SVector::<Real, 6>::zeros(); n];
        let mut out: Vec<Real> = a.iter().zip(&self.delta).map(|(a, d)| a * d).collect();
        for i in (0..n).rev() {
            let link = &self.links[i];
            let f = forces[i] + link.e * states[i];
            let sf = link.s().tr_mul(&f);
            for j in 0..link.ndofs {
                out[link.first_dof + j] += sf[j];
            }
            if let Some(parent) = link.parent {
                forces[parent] += link.shift_force(&f);
            }
        }
        out
    }
}
