//! The predictor of a system without a flow of its own: the Euler–Poincaré flow
//! integrated in the step's chart (the bodies in space, a user's group).

use crate::flow::{hermite, rk4_step, FlowGuess, FlowStart, MAX_SUBSTEPS, SUBSTEP_ANGLE};
use crate::group::{ConfigurationGroup, GroupChart};
use crate::system::{ElementOf, System};
use lgsvi_lie::LieGroup;
use nalgebra::SVector;

/// The predictor of a system without a flow of its own ([`crate::System::flow_guess`]
/// unavailable) that gives `ξ(μ)` in closed form ([`crate::System::velocity_from_momentum`])
/// and its configuration force ([`crate::System::local_derivatives`]): the
/// Euler–Poincaré flow integrated in the step's chart itself, on `(y, μ)` with
/// `ẏ = A(y)⁻¹ ξ` and `μ̇ = ad_ξᵀ μ + p + F` at `g = g_k Φ(y)` (classical RK4, substeps of at
/// most [`crate::flow`]'s `SUBSTEP_ANGLE` of rotation and of `2√|ΔΩ|` of the forces' push, cubic Hermite
/// interpolation of `y` at the nodes). [`FlowGuess::Unavailable`] where either closed form
/// is missing, a value is not finite, or `y` leaves the chart's domain.
pub(crate) fn chart_flow<S, C, const D: usize>(
    system: &S,
    chart: &C,
    start: &FlowStart<'_, S::Group, D>,
    out: &mut [SVector<f64, D>],
) -> FlowGuess<ElementOf<S, D>>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
{
    use FlowGuess::Unavailable;
    let base = start.base;
    // (ẏ, μ̇) at (y, μ), t into the step.
    let rate = |t: f64, y: &SVector<f64, D>, mu: &SVector<f64, D>| {
        chart.check_domain(y).ok()?;
        let time = start.time + t;
        let phi = chart.to_group(y);
        let g = base.compose(&phi);
        let xi = system.velocity_from_momentum(time, &g, mu)?;
        let p = system
            .local_derivatives(time, &g, &xi, false)?
            .configuration_gradient;
        let y_dot = chart.chart_velocity(y, &phi, &xi).ok()?;
        let mut mu_dot = <S::Group as ConfigurationGroup<D>>::coadjoint_generator(mu) * xi + p;
        if let Some(force) = start.force_value {
            mu_dot += force(time, &g, &xi);
        }
        (y_dot.iter().chain(mu_dot.iter()).all(|x| x.is_finite())).then_some((y_dot, mu_dot))
    };
    let (h, times) = (start.h, start.times);
    let (mut y, mut mu) = (SVector::<f64, D>::zeros(), *start.momentum);
    let Some((mut y_dot, mut mu_dot)) = rate(0.0, &y, &mu) else {
        return Unavailable;
    };
    // The substeps: the rotation, and the push of the configuration force and the force
    // (μ̇ less its coadjoint part).
    let velocity = start.velocity;
    let push = mu_dot - <S::Group as ConfigurationGroup<D>>::coadjoint_generator(&mu) * velocity;
    let pushed = system
        .velocity_from_momentum(start.time, base, &(mu + push))
        .map_or(0.0, |moved| {
            // The rotational part where the group has one: `√|ΔΩ|` is a frequency for an
            // angle (a pendulum's `√(mgl/J)`), not for a translation (`√|Δv|` has no time
            // scale: under uniform gravity it asked for 14 substeps where 4 do).
            let change = moved - velocity;
            let speed = <S::Group as ConfigurationGroup<D>>::angular_speed;
            let has_rotation = speed(&SVector::<f64, D>::repeat(1.0)) > 0.0;
            2.0 * if has_rotation {
                speed(&change)
            } else {
                change.norm()
            }
            .sqrt()
        });
    let frequency = <S::Group as ConfigurationGroup<D>>::angular_speed(velocity) + pushed;
    let wanted = (h * frequency / SUBSTEP_ANGLE).ceil();
    if wanted.is_nan() || wanted > MAX_SUBSTEPS as f64 {
        return Unavailable;
    }
    let substeps = (wanted as usize).max(3);
    let dt = h / substeps as f64;
    let mut next_node = 0;
    for s in 0..substeps {
        let t0 = s as f64 * dt;
        let Some((y1, mu1)) = rk4_step(rate, t0, dt, (y, mu), (y_dot, mu_dot)) else {
            return Unavailable;
        };
        let Some((y1_dot, mu1_dot)) = rate(t0 + dt, &y1, &mu1) else {
            return Unavailable;
        };
        let last = s + 1 == substeps;
        while next_node < times.len() && (last || times[next_node] <= t0 + dt) {
            let u = ((times[next_node] - t0) / dt).clamp(0.0, 1.0);
            out[next_node] = hermite((y, y_dot), (y1, y1_dot), u, dt);
            next_node += 1;
        }
        (y, mu, y_dot, mu_dot) = (y1, mu1, y1_dot, mu1_dot);
    }
    FlowGuess::Written(chart.to_group(&y))
}
