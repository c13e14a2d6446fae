//! What several of the crate's integration tests share.

use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::lie::LieGroup;
use lgsvi_mechanics::State;

/// The largest entry of `(log(R_exactᵀ R), Ω − Ω_exact)` against the exact free-body motion
/// (Jacobi elliptic functions, not the integrator): a checked run's own measure.
pub fn truth(exact: &FreeRigidBodyExact, state: &State) -> f64 {
    let e = exact.state(state.time).unwrap();
    let theta = e.attitude().inverse().compose(state.attitude()).log();
    theta.amax().max((state.velocity - e.velocity).amax())
}
