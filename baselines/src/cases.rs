//! The baselines' problems of `lgsvi_cases`' named cases, so that every comparison runs
//! the yardsticks on the same inputs as lgsvi.

use crate::{Model, SpaceModel, SpaceState, State};
use lgsvi_cases::{Case, Kind};
use nalgebra::Vector3;

/// The model and start of an SO(3) case (`A`, `B`, `C`, `B_mg1`, `C_mg1`): principal
/// moments, `m g` and `ρ` of a heavy top (zero and `e₃` for a free body), `R(0)` and
/// `Π(0) = JΩ(0)`. `None` for a case these models cannot hold (a full inertia tensor, a
/// torque, a body in space).
///
/// ```
/// let b = lgsvi_cases::case("B")?;
/// let (model, start) = lgsvi_baselines::so3_problem(b).unwrap();
/// assert_eq!((model.inertia, model.mg), ([4.8, 3.0, 3.8], 9.81));
/// assert_eq!(start.momentum.x, 4.8 * 0.5);
/// # Ok::<(), lgsvi_cases::CaseError>(())
/// ```
pub fn so3_problem(case: &Case) -> Option<(Model, State)> {
    if !matches!(case.kind, Kind::FreeBody | Kind::HeavyTop) {
        return None;
    }
    let model = Model {
        inertia: case.principal_moments()?,
        mg: case.weight().unwrap_or(0.0),
        rho: case.center_of_mass.unwrap_or_else(Vector3::z),
    };
    let start = State {
        attitude: case.attitude0,
        momentum: Vector3::from(model.inertia).component_mul(&case.omega0),
    };
    Some((model, start))
}

/// The model and start of a body in space or a torqued body (`O1`, `F1`): principal
/// moments, mass (1 without an orbit), `μ` (0 without one), the body torque, and the
/// start `(R, Ω, x, ẋ)` (`x = ẋ = 0` without an orbit). `None` for a heavy top or a full
/// inertia tensor.
///
/// ```
/// let o1 = lgsvi_cases::case("O1")?;
/// let (model, start) = lgsvi_baselines::space_problem(o1).unwrap();
/// assert_eq!((model.mass, model.mu), (1.0, 1.0));
/// assert_eq!(start.position.x, 3.0);
/// # Ok::<(), lgsvi_cases::CaseError>(())
/// ```
pub fn space_problem(case: &Case) -> Option<(SpaceModel, SpaceState)> {
    if case.kind == Kind::HeavyTop {
        return None;
    }
    let model = SpaceModel {
        inertia: case.principal_moments()?,
        mass: case.mass.unwrap_or(1.0),
        mu: case.mu.unwrap_or(0.0),
        torque: case.torque.unwrap_or_else(Vector3::zeros),
    };
    let start = SpaceState {
        attitude: case.attitude0,
        omega: case.omega0,
        position: case.position0.unwrap_or_else(Vector3::zeros),
        velocity: case.velocity0.unwrap_or_else(Vector3::zeros),
    };
    Some((model, start))
}
