// Added by whisker-slam (vendor/PATCHES.md, patch 9): not part of Rapier 0.36.1.
//! Forward kinematics without the dense body Jacobians. A link's body Jacobian `J_i`
//! (6 × ndofs, at its centre of mass `c_i`) is, column by column, its ancestors' own joint
//! columns moved rigidly to `c_i`: for a DoF `a` of link `q`, `J_i[:, a] = (v + ω × (c_i −
//! c_q), ω)` with `(v, ω) = S_q[:, a]`, `S_q` the joint's own columns at `c_q`. So every
//! product with `Jᵀ` is a pass over the branch or the tree carrying a wrench `(f, τ)` from
//! a centre of mass to its parent's (`τ += (c_i − c_p) × f`, `c_i − c_p = shift02 +
//! shift23`), each joint taking `S_qᵀ·(f, τ)` of the wrench that reaches it:
//! `Σ_i J_i[:, a]ᵀ w_i = S_q[:, a]ᵀ Σ_{i below q} T(c_i − c_q)ᵀ w_i`, the same sum in
//! another order (equal up to rounding). A child module of `multibody`, so it reads the
//! multibody's private fields.

use super::Multibody;
use super::super::multibody_link::MultibodyLinkVec;
use crate::math::{ANG_DIM, DIM, Jacobian, Pose, Real, SPATIAL_DIM};
use crate::utils::{CrossProductMatrix, vect_to_na};
use na::{self, Dyn, Matrix, SMatrix, SVector, StorageMut, U1};

/// A wrench at a centre of mass: force (first `DIM` rows), torque (the rest).
pub(super) type Wrench = SVector<Real, SPATIAL_DIM>;

/// `w` (at link `i`'s centre of mass) moved to its parent's centre of mass.
fn to_parent(links: &MultibodyLinkVec, i: usize, w: &mut Wrench) {
    let link = &links[i];
    let d = vect_to_na(link.shift02 + link.shift23);
    let f = w.fixed_rows::<DIM>(0).into_owned();
    let mut t = w.fixed_rows_mut::<ANG_DIM>(DIM);
    t += d.cross(&f);
}

impl Multibody {
    /// whisker-slam patch 9: each link's own joint columns of its body Jacobian (the columns
    /// `update_body_jacobians` writes at the link's own DoFs: the joint's Jacobian, its linear
    /// rows moved to the centre of mass), and nothing else; the dense body Jacobians become
    /// stale.
    pub(super) fn update_own_jacobians(&mut self) {
        self.own_jacobians
            .resize(self.links.len(), SMatrix::zeros());
        for i in 0..self.links.len() {
            let link = &self.links[i];
            let parent_to_world = if i != 0 {
                self.links[link.parent_internal_id].local_to_world
            } else {
                Pose::IDENTITY
            };
            let ndofs = link.joint.ndofs();
            let mut j = SMatrix::<Real, SPATIAL_DIM, SPATIAL_DIM>::zeros();
            link.joint.jacobian(
                &(parent_to_world.rotation * link.joint.data.local_frame1.rotation),
                &mut j.columns_mut(0, ndofs),
            );
            let w = j.fixed_rows::<ANG_DIM>(DIM).into_owned();
            let shift_tr = vect_to_na(link.shift23).gcross_matrix_tr();
            j.fixed_rows_mut::<DIM>(0).gemm(1.0, &shift_tr, &w, 1.0);
            self.own_jacobians[i] = j;
        }
        self.jacobians_stale = true;
    }

    /// whisker-slam patch 9: `out += Σ_i J_iᵀ·wrenches[i]` over every link, by one pass from
    /// the tips (`wrenches` is consumed: each ends as its subtree's total at its link).
    pub(super) fn add_tree_forces<S: StorageMut<Real, Dyn>>(
        &self,
        wrenches: &mut [Wrench],
        out: &mut Matrix<Real, Dyn, U1, S>,
    ) {
        for i in (1..self.links.len()).rev() {
            let mut w = wrenches[i];
            to_parent(&self.links, i, &mut w);
            wrenches[self.links[i].parent_internal_id] += w;
        }
        for (i, link) in self.links.iter().enumerate() {
            let ndofs = link.joint.ndofs();
            out.rows_mut(link.assembly_id, ndofs).gemv_tr(
                1.0,
                &self.own_jacobians[i].columns(0, ndofs),
                &wrenches[i],
                1.0,
            );
        }
    }

    /// whisker-slam patch 9: `out += J_{link}ᵀ·wrench`, by one pass up the link's branch.
    pub(super) fn add_branch_forces<S: StorageMut<Real, Dyn>>(
        &self,
        link_id: usize,
        mut wrench: Wrench,
        out: &mut Matrix<Real, Dyn, U1, S>,
    ) {
        let mut i = link_id;
        loop {
            let link = &self.links[i];
            let ndofs = link.joint.ndofs();
            out.rows_mut(link.assembly_id, ndofs).gemv_tr(
                1.0,
                &self.own_jacobians[i].columns(0, ndofs),
                &wrench,
                1.0,
            );
            if i == 0 {
                break;
            }
            to_parent(&self.links, i, &mut wrench);
            i = link.parent_internal_id;
        }
    }

    /// whisker-slam patch 9: link `link_id`'s dense body Jacobian from the own columns, row
    /// by row (`J[r, :] = (Jᵀ·e_r)ᵀ`), for the rare callers that need the matrix itself.
    pub(super) fn dense_body_jacobian(&self, link_id: usize) -> Jacobian<Real> {
        let mut j = Jacobian::zeros(self.ndofs);
        let mut row = na::DVector::zeros(self.ndofs);
        for r in 0..SPATIAL_DIM {
            row.fill(0.0);
            self.add_branch_forces(link_id, Wrench::ith(r, 1.0), &mut row);
            j.row_mut(r).tr_copy_from(&row);
        }
        j
    }
}
