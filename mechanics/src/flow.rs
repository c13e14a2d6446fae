//! The predictor's guess from the system's own equations of motion: the Euler–Poincaré
//! flow over one step, integrated by the classical Runge–Kutta method on a unit quaternion
//! and the body momentum, and taken into the step's chart at the nodes.
//!
//! On long steps the last step's Galerkin curve, continued by polynomial extrapolation,
//! is a poor guess (relative residual 0.1 at `h = 1` on the paper's rigid body, against
//! 3e-4 at `h = 0.5`), and every decade it misses costs a Newton iteration (an
//! assembly with Hessians and an LU). A few Runge–Kutta substeps of the equations of
//! motion cost a few evaluations of `Ω(μ)` and, for a system that depends on the
//! attitude, of `ℓ`'s gradient.
//!
//! The attitude is integrated as a quaternion rather than in the chart: `q̇ = ½ q ⊗ Ω`
//! needs no chart differential (`A(ξ)⁻¹` of the exp chart costs a `sin_cos` and a series
//! per evaluation), and the chart enters once per node.

use crate::forces::ForceJet;
use crate::group::{ConfigurationGroup, GroupChart, Rotations, StepGroup};
use crate::lagrangian::Lagrangian;
use lgsvi_lie::so3::vee;
use lgsvi_lie::SO3;
use nalgebra::{Matrix3, Quaternion, SVector, UnitQuaternion, Vector3};
use std::ops::{Add, Mul};

/// The largest rotation one Runge–Kutta substep takes (radians). The guess is accurate to
/// about `(angle)⁴/100` relative, so 0.25 rad gives ~1e-5 on the paper's bodies: below
/// the Newton solver's chord threshold.
pub(crate) const SUBSTEP_ANGLE: f64 = 0.25;

/// At most this many substeps per step (a guess, not the solution: beyond it the
/// continued Galerkin curve is used instead).
pub(crate) const MAX_SUBSTEPS: usize = 64;

/// The flow's equations at one time: the system, the step's start and its total force.
struct Flow<'a, L> {
    system: &'a L,
    base: &'a Matrix3<f64>,
    start: &'a FlowStart<'a, Rotations, 3>,
    /// `(Bᵀa, b)` for `ℓ = k(Ω) + aᵀRb` ([`Lagrangian::linear_attitude_term`]) where the
    /// force does not read the attitude: then `p = b × R(q)ᵀ(Bᵀa)` and `R` is never formed.
    field: Option<(Vector3<f64>, Vector3<f64>)>,
}

impl<L: Lagrangian> Flow<'_, L> {
    /// `(q̇, μ̇)` at `(q, μ)`, `t` into the step: `q̇ = ½ q ⊗ (0, Ω)` and
    /// `μ̇ = μ × Ω + p + F`, with `Ω` from the system's closed-form inverse Legendre
    /// transform at `R = B R(q)`, `p` the left-trivialised configuration force
    /// `p_c = ⟨Rᵀ ∂ℓ/∂R, ê_c⟩` and `F` the step's force. `None` where `Ω` has no closed
    /// form or a value is not finite.
    fn rate(
        &self,
        t: f64,
        q: &Quaternion<f64>,
        mu: &Vector3<f64>,
    ) -> Option<(Quaternion<f64>, Vector3<f64>)> {
        let system = self.system;
        // A left-invariant ℓ does not depend on R, nor does its Ω(μ): skip the attitude
        // unless the force reads it.
        let left_invariant = system.is_left_invariant();
        let force_reads_attitude =
            self.start.force.is_some() && self.start.force_reads_configuration;
        let r = if (left_invariant || self.field.is_some()) && !force_reads_attitude {
            *self.base
        } else {
            // R(q/|q|): the Runge–Kutta stages leave the unit sphere by O(dt⁵).
            self.base
                * UnitQuaternion::from_quaternion(*q)
                    .to_rotation_matrix()
                    .matrix()
        };
        let omega = system.velocity_from_momentum(&r, mu)?;
        let q_dot = q * Quaternion::from_imag(omega * 0.5);
        let mut mu_dot = mu.cross(&omega);
        match self.field {
            // M = Rᵀa bᵀ, whose axial vector is b × Rᵀa; R(q/|q|)ᵀ applied to Bᵀa.
            Some((field, body_vector)) => {
                let rotated = UnitQuaternion::from_quaternion(*q).inverse_transform_vector(&field);
                mu_dot += body_vector.cross(&rotated);
            }
            None if !left_invariant => mu_dot += configuration_force(system, &r, &omega),
            None => {}
        }
        if let Some(force) = self.start.force_value {
            mu_dot += force(self.start.time + t, &SO3::from_matrix_unchecked(r), &omega);
        }
        (q_dot
            .coords
            .iter()
            .chain(mu_dot.iter())
            .all(|x| x.is_finite()))
        .then_some((q_dot, mu_dot))
    }
}

/// `p_c = ⟨Rᵀ ∂ℓ/∂R, ê_c⟩`, the left-trivialised force of an attitude-dependent `ℓ`.
fn configuration_force<L: Lagrangian>(
    system: &L,
    r: &Matrix3<f64>,
    omega: &Vector3<f64>,
) -> Vector3<f64> {
    let m = r.transpose() * system.derivatives(r, omega).attitude_gradient;
    vee(&(m - m.transpose()))
}

/// The flow's angular frequency at the step's start, for the substep size: `|Ω|` (the
/// rotation itself) plus, where forces act, `2√|ΔΩ|` with `ΔΩ = Ω(μ + p + F) − Ω(μ)` the
/// change of velocity the configuration force `p` and the step's force `F` make in unit
/// time (`√|ΔΩ|` is a pendulum's `√(mgl/J)` at a right angle), plus the rate
/// `|Ω(F_ξ)|` (Frobenius) at which a velocity-dependent force (damping) relaxes the
/// motion. On the paper's heavy top at `h = 2`, substeps sized by `|Ω|` alone leave the
/// guess's relative residual above the solver's chord threshold (1e-4), and every step
/// forms a second Newton matrix; with `2√|ΔΩ|` added it falls well below the threshold,
/// and a step forms one Newton matrix (after the first step, where the top starts upright
/// and `p = 0`).
fn frequency<L: Lagrangian>(
    system: &L,
    start: &FlowStart<'_, Rotations, 3>,
    base: &Matrix3<f64>,
) -> f64 {
    let (mu, omega) = (start.momentum, start.velocity);
    let rotation = omega.norm();
    let mut push = Vector3::zeros();
    let mut relaxation = 0.0;
    if !system.is_left_invariant() {
        push += configuration_force(system, base, omega);
    }
    if let Some(force) = start.force {
        let jet = force(start.time, &SO3::from_matrix_unchecked(*base), omega);
        push += jet.value;
        // Ω(μ) is linear for the built-in systems: the columns of Ω(F_ξ).
        let zero = system.velocity_from_momentum(base, &Vector3::zeros());
        for c in 0..3 {
            let column = jet.velocity.column(c).into_owned();
            match (system.velocity_from_momentum(base, &column), zero) {
                (Some(moved), Some(zero)) => relaxation += (moved - zero).norm_squared(),
                _ => relaxation = f64::INFINITY,
            }
        }
    }
    if push == Vector3::zeros() && relaxation == 0.0 {
        return rotation;
    }
    let pushed = match system.velocity_from_momentum(base, &(mu + push)) {
        Some(pushed) => 2.0 * (pushed - omega).norm().sqrt(),
        None => 0.0,
    };
    rotation + pushed + relaxation.sqrt()
}

/// One classical RK4 step of `rate` over `[t0, t0 + dt]` from `(y, μ)` with the slopes
/// `k1` there (the substeps' end slopes are reused as the next start's); `None` where a
/// stage is not defined. Both flows use it: on `(q, μ)` and in the chart on `(y, μ)`.
pub(crate) fn rk4_step<Y, M>(
    rate: impl Fn(f64, &Y, &M) -> Option<(Y, M)>,
    t0: f64,
    dt: f64,
    (y, mu): (Y, M),
    k1: (Y, M),
) -> Option<(Y, M)>
where
    Y: Copy + Add<Output = Y> + Mul<f64, Output = Y>,
    M: Copy + Add<Output = M> + Mul<f64, Output = M>,
{
    let stage = |k: &(Y, M), c: f64| rate(t0 + c, &(y + k.0 * c), &(mu + k.1 * c));
    let k2 = stage(&k1, 0.5 * dt)?;
    let k3 = stage(&k2, 0.5 * dt)?;
    let k4 = stage(&k3, dt)?;
    Some((
        y + (k1.0 + (k2.0 + k3.0) * 2.0 + k4.0) * (dt / 6.0),
        mu + (k1.1 + (k2.1 + k3.1) * 2.0 + k4.1) * (dt / 6.0),
    ))
}

/// The cubic Hermite interpolant between `(y₀, ẏ₀)` and `(y₁, ẏ₁)` a substep `dt` apart,
/// at the fraction `u` of it (fourth order, as RK4).
pub(crate) fn hermite<Y>((y0, d0): (Y, Y), (y1, d1): (Y, Y), u: f64, dt: f64) -> Y
where
    Y: Add<Output = Y> + Mul<f64, Output = Y>,
{
    let (u2, u3) = (u * u, u * u * u);
    y0 * (2.0 * u3 - 3.0 * u2 + 1.0)
        + d0 * ((u3 - 2.0 * u2 + u) * dt)
        + y1 * (3.0 * u2 - 2.0 * u3)
        + d1 * ((u3 - u2) * dt)
}

/// What a flow predictor ([`crate::System::flow_guess`]) found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FlowGuess<E> {
    /// The guess is written; the flow's configuration at the step's end relative to its
    /// start (`g_k⁻¹ g(h)`), against which the converged step is checked.
    Written(E),
    /// The flow turns the body by `angle` (≥ the chart's maximal rotation angle) relative
    /// to the step's start by `time` into the step: the chart cannot represent the step,
    /// and a root Newton found would be an aliased one.
    LeavesChart {
        /// Time into the step.
        time: f64,
        /// The rotation angle reached.
        angle: f64,
    },
    /// No flow to follow (no closed-form `ξ(μ)`, a non-finite value, a node the chart's
    /// inverse refuses, or too many substeps needed): the guess comes from elsewhere.
    Unavailable,
}

/// The rotation angle of a (not necessarily unit) quaternion that has moved continuously
/// from the identity, in `[0, 2π]`: past a half turn its scalar part is negative.
fn continuous_angle(q: &Quaternion<f64>) -> f64 {
    2.0 * q.imag().norm().atan2(q.w)
}

/// Whether a quaternion's [`continuous_angle`] reaches `limit`, with `boundary =
/// cos(limit/2)`: the half angle `φ = atan2(|v|, w) ∈ [0, π]` has `cos φ = w/|q|`, which
/// falls as `φ` grows, so where `w/|q|` is above `boundary` by far more than the rounding
/// of either side (1e-6) the angle is below `limit` and the `atan2` (a costly call, at
/// every substep) is not needed. Near the boundary the angle itself decides, so every
/// decision is the one the angle alone would make.
fn reaches(q: &Quaternion<f64>, limit: f64, boundary: f64) -> Option<f64> {
    let size = q.norm();
    if q.w > (boundary + 1e-6) * size {
        return None;
    }
    let angle = continuous_angle(q);
    (angle >= limit).then_some(angle)
}

/// Writes into `out[i]` the chart coordinates at `start.times[i]` (ascending, in
/// `[0, h]`) of the flow from `(start.base, start.momentum)` with initial velocity
/// `start.velocity`, under the step's force: classical RK4 on `(q, μ)` with substeps of
/// at most [`SUBSTEP_ANGLE`] of rotation, cubic Hermite interpolation of `q` between
/// substeps (the same order), each node's coordinates on the chart's branch nearest the
/// node before (`ξ¹ = 0`). The rotation is followed continuously (the quaternion's
/// angle): where it reaches the chart's maximal rotation angle the step cannot be
/// represented ([`FlowGuess::LeavesChart`]); a Cayley chart's inverse would silently
/// return the aliased rotation. `out` may be partly written unless the result is
/// [`FlowGuess::Written`].
pub(crate) fn flow_guess<L: Lagrangian, C: GroupChart<Rotations, 3>>(
    system: &L,
    chart: &C,
    start: &FlowStart<'_, Rotations, 3>,
    out: &mut [Vector3<f64>],
) -> FlowGuess<SO3> {
    use FlowGuess::Unavailable;
    let (h, times) = (start.h, start.times);
    let base = start.base.matrix();
    let wanted = (h * frequency(system, start, base) / SUBSTEP_ANGLE).ceil();
    if wanted.is_nan() || wanted > MAX_SUBSTEPS as f64 {
        return Unavailable;
    }
    let field = system
        .linear_attitude_term()
        .filter(|_| !system.is_left_invariant())
        .filter(|_| !(start.force.is_some() && start.force_reads_configuration))
        .map(|(field, body_vector)| (base.transpose() * field, body_vector));
    let flow = Flow {
        system,
        base,
        start,
        field,
    };
    let limit = chart.max_rotation_angle();
    let boundary = (0.5 * limit).cos();
    let substeps = (wanted as usize).max(2);
    let dt = h / substeps as f64;
    let (mut q, mut mu) = (Quaternion::identity(), *start.momentum);
    let Some((mut q_dot, mut mu_dot)) = flow.rate(0.0, &q, &mu) else {
        return Unavailable;
    };
    let mut near = Vector3::zeros();
    let mut next_node = 0;
    for s in 0..substeps {
        let t0 = s as f64 * dt;
        let rate = |t: f64, q: &Quaternion<f64>, mu: &Vector3<f64>| flow.rate(t, q, mu);
        let Some((q1, mu1)) = rk4_step(rate, t0, dt, (q, mu), (q_dot, mu_dot)) else {
            return Unavailable;
        };
        let Some((q1_dot, mu1_dot)) = flow.rate(t0 + dt, &q1, &mu1) else {
            return Unavailable;
        };
        if let Some(angle) = reaches(&q1, limit, boundary) {
            return FlowGuess::LeavesChart {
                time: t0 + dt,
                angle,
            };
        }
        let last = s + 1 == substeps;
        while next_node < times.len() && (last || times[next_node] <= t0 + dt) {
            let u = ((times[next_node] - t0) / dt).clamp(0.0, 1.0);
            let qi = hermite((q, q_dot), (q1, q1_dot), u, dt);
            let rotation = UnitQuaternion::from_quaternion(qi).to_rotation_matrix();
            match chart.to_algebra_near(&SO3::from_matrix_unchecked(*rotation.matrix()), &near) {
                Ok(xi) if xi.iter().all(|x| x.is_finite()) => {
                    out[next_node] = xi;
                    near = xi;
                }
                _ => return Unavailable,
            }
            next_node += 1;
        }
        (q, mu, q_dot, mu_dot) = (q1, mu1, q1_dot, mu1_dot);
    }
    FlowGuess::Written(SO3::from_matrix_unchecked(
        *UnitQuaternion::from_quaternion(q)
            .to_rotation_matrix()
            .matrix(),
    ))
}

/// The total force along a step, `(t, g, ξ) ↦` its [`ForceJet`] (the system's force and
/// the control input), as a flow predictor receives it.
pub type ForceAlongStep<'a, G, const D: usize> =
    &'a dyn Fn(f64, &<G as ConfigurationGroup<D>>::Element<f64>, &SVector<f64, D>) -> ForceJet<D>;

/// The value alone of the same force, `(t, g, ξ) ↦ F(t, g, ξ)`: what a flow's stages read,
/// at a fraction of the cost of its [`ForceJet`].
pub type ForceValueAlongStep<'a, G, const D: usize> = &'a dyn Fn(
    f64,
    &<G as ConfigurationGroup<D>>::Element<f64>,
    &SVector<f64, D>,
) -> SVector<f64, D>;

/// The start of a step, as [`crate::System::flow_guess`] receives it.
pub struct FlowStart<'a, G: StepGroup<D>, const D: usize> {
    /// The step's start time `t_k`.
    pub time: f64,
    /// The configuration `g_k`.
    pub base: &'a G::Element<f64>,
    /// The body momentum `μ_k`.
    pub momentum: &'a SVector<f64, D>,
    /// The body velocity `ξ_k`.
    pub velocity: &'a SVector<f64, D>,
    /// The step `h`.
    pub h: f64,
    /// The node times in `[0, h]`, ascending.
    pub times: &'a [f64],
    /// The total force of a forced step (`None` for an unforced one): `F(t, g, ξ)` at the
    /// absolute time `t`.
    pub force: Option<ForceAlongStep<'a, G, D>>,
    /// The same force's value alone (`Some` exactly when [`FlowStart::force`] is): the
    /// value of its jet, bit for bit, without the derivatives.
    pub force_value: Option<ForceValueAlongStep<'a, G, D>>,
    /// Whether that force depends on the configuration (if not, it may be given any).
    pub force_reads_configuration: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shortcut decides as the angle does: quaternions of every norm and half angle,
    /// dense near both charts' limits (π for Cayley, 2π for exp: half angles π/2 and π)
    /// and at them to the last ulps, with the angle reported where it is reached.
    #[test]
    fn reaching_the_limit_is_decided_as_by_the_angle() {
        let mut halves: Vec<f64> = (0..=2000)
            .map(|k| k as f64 * std::f64::consts::PI / 2000.0)
            .collect();
        for centre in [std::f64::consts::FRAC_PI_2, std::f64::consts::PI] {
            for k in -200..=200 {
                halves.push(centre + k as f64 * 1e-9);
                halves.push(centre + k as f64 * f64::EPSILON);
            }
        }
        let mut decided = [0usize; 2];
        for limit in [std::f64::consts::PI, std::f64::consts::TAU] {
            let boundary = (0.5 * limit).cos();
            for &half in &halves {
                for size in [1e-3, 0.7, 1.0, 1.0 + 1e-9, 3.0] {
                    let axis = Vector3::new(0.3, -0.8, 0.52).normalize();
                    let imag = axis * (half.sin() * size);
                    let q = Quaternion::new(half.cos() * size, imag.x, imag.y, imag.z);
                    let angle = continuous_angle(&q);
                    let expected = (angle >= limit).then_some(angle);
                    assert_eq!(
                        reaches(&q, limit, boundary),
                        expected,
                        "half angle {half}, |q| {size}"
                    );
                    decided[usize::from(expected.is_some())] += 1;
                }
            }
        }
        // Both answers occur (the test sees the boundary from both sides).
        assert!(decided[0] > 0 && decided[1] > 0, "{decided:?}");
    }

    /// A non-finite quaternion never reaches the limit, as its NaN angle does not.
    #[test]
    fn a_non_finite_quaternion_does_not_reach_the_limit() {
        let q = Quaternion::new(f64::NAN, 0.1, 0.2, 0.3);
        assert_eq!(reaches(&q, std::f64::consts::PI, 0.0), None);
    }
}
