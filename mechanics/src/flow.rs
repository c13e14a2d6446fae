//! The predictor's guess from the system's own equations of motion: the Euler–Poincaré
//! flow over one step, integrated by the classical Runge–Kutta method in the step's chart
//! and sampled at the nodes.
//!
//! On long steps the last step's Galerkin curve, continued by polynomial extrapolation,
//! is a poor guess (measured relative residual 0.1 at `h = 1` on the paper's rigid body,
//! against 3e-4 at `h = 0.5`), and every decade it misses costs a Newton iteration (an
//! assembly with Hessians and an LU). A few Runge–Kutta substeps of the equations of
//! motion cost a few evaluations of `ℓ`'s gradient.

use crate::lagrangian::Lagrangian;
use lgsvi_lie::so3::vee;
use lgsvi_lie::{ChartKind, So3Chart};
use nalgebra::{Matrix3, Vector3};

/// The largest rotation one Runge–Kutta substep takes (radians). The guess is accurate to
/// about `(angle)⁴/100` relative, so 0.25 rad gives ~1e-5 on the paper's bodies: below
/// the Newton solver's chord threshold.
const SUBSTEP_ANGLE: f64 = 0.25;

/// At most this many substeps per step (a guess, not the solution: beyond it the
/// continued Galerkin curve is used instead).
const MAX_SUBSTEPS: usize = 64;

/// `(ξ̇, μ̇)` at `(ξ, μ)`: `ξ̇ = A(ξ)⁻¹ Ω` and `μ̇ = μ × Ω + p`, with `Ω` from the
/// system's closed-form inverse Legendre transform and `p` the left-trivialised
/// configuration force `p_c = ⟨Rᵀ ∂ℓ/∂R, ê_c⟩`. `None` where `Ω` has no closed form, `ξ`
/// leaves the chart's domain, or a value is not finite.
fn rate<L: Lagrangian>(
    system: &L,
    chart: ChartKind,
    base: &Matrix3<f64>,
    xi: &Vector3<f64>,
    mu: &Vector3<f64>,
) -> Option<(Vector3<f64>, Vector3<f64>)> {
    chart.check_rotation_domain(xi).ok()?;
    // A left-invariant ℓ does not depend on R, nor does its Ω(μ): skip the attitude.
    let left_invariant = system.is_left_invariant();
    let r = if left_invariant {
        *base
    } else {
        base * chart.rotation_matrix(xi)
    };
    let omega = system.velocity_from_momentum(&r, mu)?;
    let xi_dot = chart.rotation_left_differential_inverse(xi) * omega;
    let mut mu_dot = mu.cross(&omega);
    if !left_invariant {
        let m = r.transpose() * system.derivatives(&r, &omega).attitude_gradient;
        mu_dot += vee(&(m - m.transpose()));
    }
    (xi_dot.iter().chain(mu_dot.iter()).all(|x| x.is_finite())).then_some((xi_dot, mu_dot))
}

/// Writes into `out[i]` the chart coordinates at `times[i]` (ascending, in `[0, h]`) of
/// the flow from `(base, μ)` with initial velocity `omega`: classical RK4 on `(ξ, μ)`
/// with substeps of at most [`SUBSTEP_ANGLE`] of rotation, cubic Hermite interpolation
/// between substeps (the same order). False (and `out` partly written) where [`rate`]
/// is `None` or more than [`MAX_SUBSTEPS`] would be needed.
#[allow(clippy::too_many_arguments)]
pub(crate) fn flow_guess<L: Lagrangian>(
    system: &L,
    chart: ChartKind,
    base: &Matrix3<f64>,
    mu: &Vector3<f64>,
    omega: &Vector3<f64>,
    h: f64,
    times: &[f64],
    out: &mut [Vector3<f64>],
) -> bool {
    let wanted = (h * omega.norm() / SUBSTEP_ANGLE).ceil();
    if wanted.is_nan() || wanted > MAX_SUBSTEPS as f64 {
        return false;
    }
    let substeps = (wanted as usize).max(2);
    let dt = h / substeps as f64;
    let (mut xi, mut mu) = (Vector3::zeros(), *mu);
    let Some((mut xi_dot, mut mu_dot)) = rate(system, chart, base, &xi, &mu) else {
        return false;
    };
    let mut next_node = 0;
    for s in 0..substeps {
        let t0 = s as f64 * dt;
        let step = |xi: &Vector3<f64>, mu: &Vector3<f64>, k: &(Vector3<f64>, Vector3<f64>), c| {
            rate(system, chart, base, &(xi + k.0 * c), &(mu + k.1 * c))
        };
        let k1 = (xi_dot, mu_dot);
        let Some(k2) = step(&xi, &mu, &k1, 0.5 * dt) else {
            return false;
        };
        let Some(k3) = step(&xi, &mu, &k2, 0.5 * dt) else {
            return false;
        };
        let Some(k4) = step(&xi, &mu, &k3, dt) else {
            return false;
        };
        let xi1 = xi + (k1.0 + (k2.0 + k3.0) * 2.0 + k4.0) * (dt / 6.0);
        let mu1 = mu + (k1.1 + (k2.1 + k3.1) * 2.0 + k4.1) * (dt / 6.0);
        let Some((xi1_dot, mu1_dot)) = rate(system, chart, base, &xi1, &mu1) else {
            return false;
        };
        let last = s + 1 == substeps;
        while next_node < times.len() && (last || times[next_node] <= t0 + dt) {
            let u = ((times[next_node] - t0) / dt).clamp(0.0, 1.0);
            let (u2, u3) = (u * u, u * u * u);
            out[next_node] = xi * (2.0 * u3 - 3.0 * u2 + 1.0)
                + xi_dot * ((u3 - 2.0 * u2 + u) * dt)
                + xi1 * (3.0 * u2 - 2.0 * u3)
                + xi1_dot * ((u3 - u2) * dt);
            next_node += 1;
        }
        (xi, mu, xi_dot, mu_dot) = (xi1, mu1, xi1_dot, mu1_dot);
    }
    true
}
