//! SE(3)'s charts: every [`So3Chart`] as the rotation–translation chart `(Φ(ω), u)` (the
//! default, derivatives in closed form from the Rodrigues jets of `A(ω)` and `Φ(ω)`), and
//! [`Screw`]`(chart)`, SE(3)'s own screw-motion charts (derivatives by dual numbers).

use super::*;
use crate::se3::{blocks, split};

/// The derivatives of SE(3)'s rotation–translation chart (`A = diag(A_ω(ω), Φ(ω)ᵀ)`) in
/// closed form, from the Rodrigues jets of `A_ω` and `Φ` (which depend on `ω` alone):
/// with `x = (ω, u)`, `v = (v_ω, v_u)`,
/// `∂(Av)/∂ω = [∂_kA_ω v_ω ; ∂_kΦᵀ v_u]_k`, `∂(Aᵀg)/∂ω = [∂_kA_ωᵀ g_ω ; ∂_kΦ g_u]_k`,
/// `∇²_ω(μᵀAv) = ⟨μ_ω v_ωᵀ, ∂²A_ω⟩ + ⟨v_u μ_uᵀ, ∂²Φ⟩`, nothing in `u`. Hidden with
/// [`ChartDerivatives::rotation_translation`], which gives it.
#[doc(hidden)]
pub struct RotationTranslationDerivatives {
    /// `A_ω(ω)`'s jet.
    pub a: MatrixJet,
    /// `Φ(ω)`'s jet.
    pub phi: MatrixJet,
}

impl ChartDerivatives<6> for RotationTranslationDerivatives {
    fn differential(&self) -> SMatrix<f64, 6, 6> {
        let zero = Matrix3::zeros();
        blocks(&self.a.value, &zero, &zero, &self.phi.value.transpose())
    }
    fn differential_times(&self, v: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        let (vw, vu) = split(v);
        let zero = Matrix3::zeros();
        blocks(
            &self.a.first_times(&vw),
            &zero,
            &self.phi.first_transposed_times(&vu).transpose(),
            &zero,
        )
    }
    fn transpose_times(&self, g: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        let (gw, gu) = split(g);
        let zero = Matrix3::zeros();
        blocks(
            &self.a.first_transposed_times(&gw).transpose(),
            &zero,
            &self.phi.first_times(&gu),
            &zero,
        )
    }
    fn second(&self, mu: &SVector<f64, 6>, v: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        let (mw, mu_u) = split(mu);
        let (vw, vu) = split(v);
        let ww = self.a.second_contracted(&(mw * vw.transpose()))
            + self.phi.second_contracted(&(vu * mu_u.transpose()));
        let zero = Matrix3::zeros();
        blocks(&ww, &zero, &zero, &zero)
    }
    fn rotation_translation(&self) -> Option<&RotationTranslationDerivatives> {
        Some(self)
    }
}

/// The rotation–translation chart of SE(3), the default for every [`So3Chart`] on
/// [`RigidMotions`]: `Φ(ω, u) = (Φ(ω), u)`, so that the natural chart at `g_k = (R_k, x_k)`
/// is `(R_k Φ(ω), x_k + R_k u)`: the attitude in the SO(3) chart, the centre of mass
/// moving in the world frame (`R_k` is fixed over the step), not along a screw. A step's
/// curve is then a polynomial in the world frame for the centre of mass, as on the
/// product SO(3) × ℝ³ with the trivial chart on ℝ³ — the same family of curves, so the
/// same discrete Lagrangian and discrete map — while states, velocities `(Ω, v)` and
/// momenta keep SE(3)'s conventions. `A(ω, u) = diag(A(ω), Φ(ω)ᵀ)`: its derivatives come
/// in closed form from the Rodrigues form of `A(ω)` and `Φ(ω)`, and the translational
/// kinetic energy `½m|v|² = ½m|u̇|²` has a constant Hessian. SE(3)'s own charts (screw
/// motions, `x = M(ω)u`) are [`Screw`].
impl<C: So3Chart + Send + Sync> GroupChart<RigidMotions, 6> for C {
    fn name(&self) -> &'static str {
        self.chart_name()
    }
    /// `(Φ(ω), u)`.
    fn to_group<T: RealField + Copy>(&self, xi: &SVector<T, 6>) -> SE3<T> {
        let (w, u) = split(xi);
        SE3::new(SO3::from_matrix_unchecked(self.rotation_matrix(&w)), u)
    }
    /// `diag(A(ω), Φ(ω)ᵀ)`.
    fn left_differential<T: RealField + Copy>(&self, xi: &SVector<T, 6>) -> SMatrix<T, 6, 6> {
        let (w, _) = split(xi);
        let zero = Matrix3::zeros();
        blocks(
            &self.rotation_left_differential(&w),
            &zero,
            &zero,
            &self.rotation_matrix(&w).transpose(),
        )
    }
    /// `(A(ω)⁻¹ ξ_ω, Φ(ω) ξ_u)`, `Φ(ω)` read from `phi`: [`GroupChart::left_differential_inverse`]'s
    /// blocks applied apart, which adds none of its zero terms (no value changes).
    fn chart_velocity(
        &self,
        y: &SVector<f64, 6>,
        phi: &SE3,
        xi: &SVector<f64, 6>,
    ) -> Result<SVector<f64, 6>, LieError> {
        GroupChart::<RigidMotions, 6>::check_domain(self, y)?;
        let (w, _) = split(y);
        let (xi_w, xi_u) = split(xi);
        Ok(crate::se3::join(
            &(self.rotation_left_differential_inverse(&w) * xi_w),
            &(phi.rotation().matrix() * xi_u),
        ))
    }
    /// `diag(A(ω)⁻¹, Φ(ω))`.
    fn left_differential_inverse(
        &self,
        xi: &SVector<f64, 6>,
    ) -> Result<SMatrix<f64, 6, 6>, LieError> {
        GroupChart::<RigidMotions, 6>::check_domain(self, xi)?;
        let (w, _) = split(xi);
        let zero = Matrix3::zeros();
        Ok(blocks(
            &self.rotation_left_differential_inverse(&w),
            &zero,
            &zero,
            &self.rotation_matrix(&w),
        ))
    }
    fn to_algebra_near(
        &self,
        g: &SE3,
        near: &SVector<f64, 6>,
    ) -> Result<SVector<f64, 6>, LieError> {
        let w = self
            .rotation_vector_near(g.rotation().matrix(), &near.fixed_rows::<3>(0).into_owned())?;
        let x = g.translation();
        Ok(SVector::<f64, 6>::new(w.x, w.y, w.z, x.x, x.y, x.z))
    }
    fn check_domain(&self, xi: &SVector<f64, 6>) -> Result<(), LieError> {
        let (w, u) = split(xi);
        self.check_rotation_domain(&w)?;
        if u.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(LieError::NonFinite {
                what: "chart coordinates",
            })
        }
    }
    fn max_rotation_angle(&self) -> f64 {
        So3Chart::max_rotation_angle(self)
    }
    fn advice(&self) -> &'static str {
        so3_advice(self)
    }
    /// `Ad_{Φ⁻¹}ᵀ p = (P p_ω + u × P p_u, P p_u)` for `Φ(x) = (P, u)` (`Ad_{(R, x)} =
    /// [[R, 0], [x̂R, R]]`), `P` applied from its Rodrigues coefficients.
    fn coadjoint_to_start(&self, x: &SVector<f64, 6>, p: &SVector<f64, 6>) -> SVector<f64, 6> {
        let (w, u) = split(x);
        let (pw, pu) = split(p);
        let (turned_w, turned_u) = match self.rotation_matrix_coefficients(w.norm_squared()) {
            Some(c) => (c.times(&w, &pw), c.times(&w, &pu)),
            None => {
                let rotation = self.rotation_matrix(&w);
                (rotation * pw, rotation * pu)
            }
        };
        let q = turned_w + u.cross(&turned_u);
        SVector::<f64, 6>::new(q.x, q.y, q.z, turned_u.x, turned_u.y, turned_u.z)
    }
    /// `Ad_{Φ⁻¹}ᵀ = [[P, û P], [0, P]]` (the matrix of
    /// [`GroupChart::coadjoint_to_start`]) and `A = diag(A(ω), Pᵀ)`, from one evaluation of
    /// the Rodrigues coefficients of `P = Φ(ω)` and `A(ω)`.
    fn transport_and_differential(
        &self,
        x: &SVector<f64, 6>,
    ) -> (SMatrix<f64, 6, 6>, SMatrix<f64, 6, 6>) {
        let (w, u) = split(x);
        // SO(3)'s pair: `(P, A(ω))`.
        let (rotation, differential) =
            GroupChart::<Rotations, 3>::transport_and_differential(self, &w);
        let zero = Matrix3::zeros();
        (
            blocks(
                &rotation,
                &(crate::so3::hat(&u) * rotation),
                &zero,
                &rotation,
            ),
            blocks(&differential, &zero, &zero, &rotation.transpose()),
        )
    }
    fn with_derivatives<R>(
        &self,
        x: &SVector<f64, 6>,
        second: bool,
        f: impl FnOnce(&dyn ChartDerivatives<6>) -> R,
    ) -> R {
        let (w, _) = split(x);
        let s = w.norm_squared();
        let jets = if second {
            let s2 = Dual2_64::new(s, 1.0, 0.0);
            So3Chart::rotation_and_left_differential_coefficients(self, s2).map(|(phi, a)| {
                (
                    MatrixJet::from_rodrigues(&a, &w),
                    MatrixJet::from_rodrigues(&phi, &w),
                )
            })
        } else {
            let s1 = Dual64::new(s, 1.0);
            So3Chart::rotation_and_left_differential_coefficients(self, s1).map(|(phi, a)| {
                (
                    MatrixJet::from_rodrigues_first_order(&a, &w),
                    MatrixJet::from_rodrigues_first_order(&phi, &w),
                )
            })
        };
        match jets {
            Some((a, phi)) => f(&RotationTranslationDerivatives { a, phi }),
            None => dual_number_derivatives::<RigidMotions, Self, R, 6>(self, x, f),
        }
    }
}

/// SE(3)'s own charts, screw motions: `Φ(ω, v) = (Φ(ω), M(ω)v)` with the SO(3) chart's
/// translation map `M` (for exp, SE(3)'s exponential), as [`Chart`] gives it on [`SE3`].
/// The translation of a step's curve turns with its rotation. Choose it with lgsvi's
/// `Integrator::with_chart`: `Screw(ChartKind::Exp)`. The default SE(3) chart of
/// every [`So3Chart`] is the rotation–translation one (the `GroupChart` impl for `C`),
/// whose derivatives are in closed form; both give variational, SE(3)-equivariant
/// discrete maps.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Screw<C>(pub C);

impl<C: So3Chart + Send + Sync> GroupChart<RigidMotions, 6> for Screw<C> {
    fn name(&self) -> &'static str {
        self.0.chart_name()
    }
    fn to_group<T: RealField + Copy>(&self, xi: &SVector<T, 6>) -> SE3<T> {
        Chart::<SE3<T>>::to_group(&self.0, xi)
    }
    fn left_differential<T: RealField + Copy>(&self, xi: &SVector<T, 6>) -> SMatrix<T, 6, 6> {
        Chart::<SE3<T>>::left_differential(&self.0, xi)
    }
    fn left_differential_inverse(
        &self,
        xi: &SVector<f64, 6>,
    ) -> Result<SMatrix<f64, 6, 6>, LieError> {
        Chart::<SE3>::left_differential_inverse(&self.0, xi)
    }
    fn to_algebra_near(
        &self,
        g: &SE3,
        near: &SVector<f64, 6>,
    ) -> Result<SVector<f64, 6>, LieError> {
        let w = self
            .0
            .rotation_vector_near(g.rotation().matrix(), &near.fixed_rows::<3>(0).into_owned())?;
        let v = self.0.translation_map_inverse(&w) * g.translation();
        Ok(SVector::<f64, 6>::new(w.x, w.y, w.z, v.x, v.y, v.z))
    }
    fn check_domain(&self, xi: &SVector<f64, 6>) -> Result<(), LieError> {
        Chart::<SE3>::check_domain(&self.0, xi)
    }
    fn max_rotation_angle(&self) -> f64 {
        So3Chart::max_rotation_angle(&self.0)
    }
    fn advice(&self) -> &'static str {
        so3_advice(&self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chart::ChartKind;

    /// The rotation–translation chart's `chart_velocity` is `A(y)⁻¹ ξ` of the whole 6 × 6
    /// inverse bit for bit (every chart, points from near zero to near each chart's edge),
    /// and refuses a point outside the chart as `left_differential_inverse` does.
    #[test]
    fn the_chart_velocity_is_the_inverse_differential_applied() {
        let xi = SVector::<f64, 6>::new(0.7, -1.3, 0.4, 2.1, -0.6, 1.9);
        for chart in ChartKind::ALL {
            for scale in [
                1e-9,
                0.3,
                1.0,
                2.0,
                0.9 * So3Chart::max_rotation_angle(&chart),
            ] {
                let w = Vector3::new(0.48, -0.6, 0.64).normalize() * scale;
                let y = SVector::<f64, 6>::new(w.x, w.y, w.z, 0.5, -2.0, 0.25);
                let phi = GroupChart::<RigidMotions, 6>::to_group(&chart, &y);
                let whole = GroupChart::<RigidMotions, 6>::left_differential_inverse(&chart, &y)
                    .unwrap()
                    * xi;
                let apart =
                    GroupChart::<RigidMotions, 6>::chart_velocity(&chart, &y, &phi, &xi).unwrap();
                for k in 0..6 {
                    assert_eq!(
                        whole[k].to_bits(),
                        apart[k].to_bits(),
                        "{chart} |ω| = {scale}"
                    );
                }
            }
            let outside = SVector::<f64, 6>::new(f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0);
            let phi = SE3::identity();
            assert!(
                GroupChart::<RigidMotions, 6>::chart_velocity(&chart, &outside, &phi, &xi).is_err()
            );
        }
    }
}
