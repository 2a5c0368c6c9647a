// Added by whisker-slam (vendor/PATCHES.md, patch 6): not part of Rapier 0.36.1.
//! `Multibody::update_articulated`: the link terms of the two augmented mass matrices for
//! the articulated factorisation (`super::super::articulated`), kept out of
//! `multibody.rs` so that the patch there stays small. A child module of `multibody`, so
//! it reads the multibody's private fields.

use super::super::articulated::{ArticulatedFactor, ArticulatedLink, PAD};
use super::{Multibody, concat_rb_mass_matrix};
use crate::alloc_prelude::*;
use crate::dynamics::RigidBodySet;
use crate::math::{ANG_DIM, AngVector, DIM, Pose, Real, SPATIAL_DIM};
use crate::utils::{AngularInertiaOps, CrossProduct, CrossProductMatrix, vect_to_na};
use na::{self, SMatrix};

impl Multibody {
    /// whisker-slam patch 6: the articulated factorisations of the plain and (when
    /// `semi_implicit_coriolis`) the semi-implicit augmented mass matrices, from the same
    /// terms [`Self::update_mass_matrix`] assembles densely: each link's mass, its
    /// gyroscopic derivative and its Coriolis rows, which follow the Jacobian's recursion
    /// (`articulated` module doc). `false` (nothing set) when a joint is kinematic or a
    /// pivot block is singular: the caller assembles the dense matrices instead.
    pub(super) fn update_articulated(
        &mut self,
        dt: Real,
        bodies: &RigidBodySet,
        semi_implicit_coriolis: bool,
    ) -> bool {
        if self.links.iter().any(|l| l.joint.kinematic || l.joint.ndofs() > PAD) {
            return false;
        }
        // Δ: damping, armature and the implicit springs, as on the dense diagonal.
        let mut delta = vec![0.0; self.ndofs];
        for (i, d) in delta.iter_mut().enumerate() {
            *d = self.damping[i] * dt + self.armature[i];
        }
        for link in self.links.iter() {
            let mut idx = link.assembly_id;
            let locked = link.joint.data.locked_axes.bits();
            for a in 0..SPATIAL_DIM {
                if (locked >> a) & 1 == 0 {
                    let k = link.joint.spring_stiffness[a];
                    if k != 0.0 {
                        delta[idx] += k * dt * dt;
                    }
                    idx += 1;
                }
            }
        }

        let mut plain = Vec::with_capacity(self.links.len());
        let mut acc = Vec::with_capacity(if semi_implicit_coriolis {
            self.links.len()
        } else {
            0
        });
        for i in 0..self.links.len() {
            let link = &self.links[i];
            let rb = &bodies[link.rigid_body];
            let rb_mass = rb.mprops.effective_mass();
            let rb_inertia = rb.mprops.effective_angular_inertia().into_matrix();
            let ndofs = link.joint.ndofs();

            // The joint's own columns `S` (world frame, at the joint), as in
            // `update_body_jacobians`.
            let (parent, parent_rotation, parent_angvel) = if i != 0 {
                let parent_link = &self.links[link.parent_internal_id];
                (
                    Some(link.parent_internal_id),
                    parent_link.local_to_world.rotation,
                    bodies[parent_link.rigid_body].vels.angvel,
                )
            } else {
                (None, Pose::IDENTITY.rotation, AngVector::ZERO)
            };
            let mut joint_j = SMatrix::<Real, SPATIAL_DIM, PAD>::zeros();
            link.joint.jacobian(
                &(parent_rotation * link.joint.data.local_frame1.rotation),
                &mut joint_j.columns_mut(0, ndofs),
            );
            let s_v = joint_j.fixed_rows::<DIM>(0).into_owned();
            let s_w = joint_j.fixed_rows::<ANG_DIM>(DIM).into_owned();

            let a23 = vect_to_na(link.shift23).gcross_matrix_tr();
            let a02 = if parent.is_some() {
                vect_to_na(link.shift02).gcross_matrix_tr()
            } else {
                na::Matrix3::zeros()
            };
            let mut psi6 = SMatrix::<Real, 6, PAD>::zeros();
            psi6.fixed_rows_mut::<DIM>(0).copy_from(&(s_v + a23 * s_w));
            psi6.fixed_rows_mut::<ANG_DIM>(DIM).copy_from(&s_w);

            #[allow(clippy::useless_conversion)]
            let mass = concat_rb_mass_matrix(rb_mass, rb_inertia.into());
            plain.push(ArticulatedLink::<6> {
                parent,
                first_dof: link.assembly_id,
                ndofs,
                a: a02 + a23,
                b: na::Matrix3::zeros(),
                c: na::Matrix3::zeros(),
                psi: psi6,
                e: mass,
            });
            if !semi_implicit_coriolis {
                continue;
            }

            // The Coriolis rows' recursion, term by term as `update_mass_matrix` builds
            // `coriolis_v` and `coriolis_w`: from the parent to the joint (02), then to the
            // link's centre of mass (23).
            let w_i = vect_to_na(rb.vels.angvel).gcross_matrix();
            let r23 = vect_to_na(rb.vels.angvel.gcross(link.shift23)).gcross_matrix_tr()
                + w_i * a23;
            let (b, c, own_cv, own_cw) = if parent.is_some() {
                let w_p = vect_to_na(parent_angvel).gcross_matrix();
                let dvel = vect_to_na(
                    rb.vels.angvel.gcross(link.shift02) + 2.0 * link.joint_velocity.linvel,
                )
                .gcross_matrix_tr();
                let jl = vect_to_na(link.joint_velocity.linvel).gcross_matrix_tr();
                let jw = vect_to_na(link.joint_velocity.angvel).gcross_matrix();
                let q = dvel + jl + w_p * a02;
                (q - a23 * jw + r23, -jw, 2.0 * w_p * s_v, w_p * s_w)
            } else {
                (
                    na::Matrix3::zeros(),
                    na::Matrix3::zeros(),
                    SMatrix::<Real, DIM, PAD>::zeros(),
                    SMatrix::<Real, ANG_DIM, PAD>::zeros(),
                )
            };
            let mut psi12 = SMatrix::<Real, 12, PAD>::zeros();
            psi12.fixed_rows_mut::<6>(0).copy_from(&psi6);
            psi12
                .fixed_rows_mut::<DIM>(6)
                .copy_from(&(own_cv + a23 * own_cw + r23 * s_w));
            psi12.fixed_rows_mut::<ANG_DIM>(9).copy_from(&own_cw);

            // E = [M̃, dt·M]: the mass with `dt·` the gyroscopic derivative, and `dt·` the
            // mass applied to the Coriolis rows (`i_coriolis_dt`).
            let gyroscopic_matrix = rb.vels.angvel.gcross_matrix() * rb_inertia
                - (rb_inertia * rb.vels.angvel).gcross_matrix();
            let augmented_inertia = rb_inertia + gyroscopic_matrix * dt;
            #[allow(clippy::useless_conversion)]
            let augmented = concat_rb_mass_matrix(rb_mass, augmented_inertia.into());
            let mut e = SMatrix::<Real, 6, 12>::zeros();
            e.fixed_columns_mut::<6>(0).copy_from(&augmented);
            e.fixed_columns_mut::<6>(6).copy_from(&(mass * dt));
            acc.push(ArticulatedLink::<12> {
                parent,
                first_dof: link.assembly_id,
                ndofs,
                a: a02 + a23,
                b,
                c,
                psi: psi12,
                e,
            });
        }

        let Some(plain) = ArticulatedFactor::new(plain, delta.clone()) else {
            return false;
        };
        // whisker-slam patch 10: the root's columns of `M⁻¹` are computed on first use
        // (`solve_root_mut`), not here.
        let acc = if semi_implicit_coriolis {
            match ArticulatedFactor::new(acc, delta) {
                Some(f) => Some(f),
                None => return false,
            }
        } else {
            None
        };
        // No kinematic DoF: the identity ordering for `with_rearranged_rows_mut` users.
        self.augmented_mass_indices.clear();
        for k in 0..self.ndofs {
            self.augmented_mass_indices.keep(k);
        }
        self.articulated = Some(plain);
        self.acc_articulated = acc;
        true
    }
}
