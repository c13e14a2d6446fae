//! The built-in systems as one type per group, for programs that choose the system at run
//! time (a command line, a configuration file, a Python call): [`BuiltInSo3`] on SO(3),
//! [`BuiltInSe3`] on SE(3); a gyrostat's wheel count is [`crate::gyrostat::AnyGyrostat`]'s.
//! Each forwards every closed form of the system it holds, so a step is that system's own,
//! bit for bit.

use crate::forces::ForceJet;
use crate::group::{GroupChart, RigidMotions, StepGroup};
use crate::lagrangian::{HeavyTop, RigidBody};
use crate::lagrangian::{Lagrangian, LagrangianDerivatives};
use crate::rigid_motion::{FreeBody, OrbitingBody};
use crate::system::System;
use crate::system::{FlowGuess, FlowStart, GaussPoint, LocalDerivatives};
use lgsvi_lie::SE3;
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};

/// A built-in SO(3) system, the free rigid body or the heavy top: one type, so that
/// studies and command lines need not be generic. The closed forms of both are forwarded
/// (the default dual numbers would be ~10× slower).
#[derive(Debug, Clone, Copy)]
pub enum BuiltInSo3 {
    /// The free rigid body.
    Free(RigidBody),
    /// The heavy top.
    Top(HeavyTop),
}

crate::system::so3_system! {
    impl[] for BuiltInSo3;
}

impl From<RigidBody> for BuiltInSo3 {
    fn from(body: RigidBody) -> Self {
        BuiltInSo3::Free(body)
    }
}

impl From<HeavyTop> for BuiltInSo3 {
    fn from(top: HeavyTop) -> Self {
        BuiltInSo3::Top(top)
    }
}

impl Lagrangian for BuiltInSo3 {
    fn lagrangian<T: RealField + Copy>(&self, r: &Matrix3<T>, w: &Vector3<T>) -> T {
        match self {
            BuiltInSo3::Free(s) => Lagrangian::lagrangian(s, r, w),
            BuiltInSo3::Top(s) => Lagrangian::lagrangian(s, r, w),
        }
    }
    fn is_left_invariant(&self) -> bool {
        match self {
            BuiltInSo3::Free(s) => Lagrangian::is_left_invariant(s),
            BuiltInSo3::Top(s) => Lagrangian::is_left_invariant(s),
        }
    }
    fn symmetry_axis(&self) -> Option<Vector3<f64>> {
        match self {
            BuiltInSo3::Free(s) => s.symmetry_axis(),
            BuiltInSo3::Top(s) => s.symmetry_axis(),
        }
    }
    fn linear_attitude_term(&self) -> Option<(Vector3<f64>, Vector3<f64>)> {
        match self {
            BuiltInSo3::Free(s) => s.linear_attitude_term(),
            BuiltInSo3::Top(s) => s.linear_attitude_term(),
        }
    }
    fn natural_frequency(&self) -> f64 {
        match self {
            BuiltInSo3::Free(s) => s.natural_frequency(),
            BuiltInSo3::Top(s) => s.natural_frequency(),
        }
    }
    fn velocity_from_momentum(&self, r: &Matrix3<f64>, mu: &Vector3<f64>) -> Option<Vector3<f64>> {
        match self {
            BuiltInSo3::Free(s) => Lagrangian::velocity_from_momentum(s, r, mu),
            BuiltInSo3::Top(s) => Lagrangian::velocity_from_momentum(s, r, mu),
        }
    }
    fn model_breakdown(&self, r: &Matrix3<f64>, w: &Vector3<f64>) -> Option<String> {
        match self {
            BuiltInSo3::Free(s) => Lagrangian::model_breakdown(s, r, w),
            BuiltInSo3::Top(s) => Lagrangian::model_breakdown(s, r, w),
        }
    }
    fn parameter_names(&self) -> Vec<String> {
        match self {
            BuiltInSo3::Free(s) => Lagrangian::parameter_names(s),
            BuiltInSo3::Top(s) => Lagrangian::parameter_names(s),
        }
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        r: &Matrix3<T>,
        w: &Vector3<T>,
    ) -> T {
        match self {
            BuiltInSo3::Free(s) => Lagrangian::parameter_lagrangian(s, index, r, w),
            BuiltInSo3::Top(s) => Lagrangian::parameter_lagrangian(s, index, r, w),
        }
    }
    // Forwarded: the built-ins' closed forms are ~10× faster than the default dual numbers.
    fn derivatives(&self, r: &Matrix3<f64>, w: &Vector3<f64>) -> LagrangianDerivatives {
        match self {
            BuiltInSo3::Free(s) => s.derivatives(r, w),
            BuiltInSo3::Top(s) => s.derivatives(r, w),
        }
    }
}

/// A built-in system on SE(3), the free body in space or the body orbiting a point mass:
/// one type, so that programs need not be generic. Every method of
/// [`System`] is forwarded, the closed forms above all (`local_derivatives`:
/// without them a step takes ℓ's derivatives by dual numbers, about 20× slower).
#[derive(Debug, Clone, Copy)]
pub enum BuiltInSe3 {
    /// The free rigid body in space.
    Free(FreeBody),
    /// The rigid body orbiting a point mass (MacCullagh's potential).
    Orbit(OrbitingBody),
}

impl From<FreeBody> for BuiltInSe3 {
    fn from(body: FreeBody) -> Self {
        BuiltInSe3::Free(body)
    }
}

impl From<OrbitingBody> for BuiltInSe3 {
    fn from(body: OrbitingBody) -> Self {
        BuiltInSe3::Orbit(body)
    }
}

/// `$body` with the variant's system bound to `s`.
macro_rules! each_motion {
    ($self:expr, $s:ident => $body:expr) => {
        match $self {
            BuiltInSe3::Free($s) => $body,
            BuiltInSe3::Orbit($s) => $body,
        }
    };
}

impl System<6> for BuiltInSe3 {
    type Group = RigidMotions;
    fn lagrangian<T: RealField + Copy>(&self, t: f64, g: &SE3<T>, xi: &SVector<T, 6>) -> T {
        each_motion!(self, s => s.lagrangian(t, g, xi))
    }
    fn is_left_invariant(&self) -> bool {
        each_motion!(self, s => s.is_left_invariant())
    }
    fn parameter_names(&self) -> Vec<String> {
        each_motion!(self, s => s.parameter_names())
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        t: f64,
        g: &SE3<T>,
        xi: &SVector<T, 6>,
    ) -> T {
        each_motion!(self, s => s.parameter_lagrangian(index, t, g, xi))
    }
    fn parameter_point_derivatives<C: GroupChart<RigidMotions, 6>>(
        &self,
        index: usize,
        chart: &C,
        point: &GaussPoint<'_, RigidMotions, 6>,
        out: &mut <RigidMotions as StepGroup<6>>::Jet,
    ) -> bool {
        each_motion!(self, s => s.parameter_point_derivatives(index, chart, point, out))
    }
    fn symmetry_generator(&self) -> Option<SVector<f64, 6>> {
        each_motion!(self, s => s.symmetry_generator())
    }
    fn velocity_from_momentum(
        &self,
        t: f64,
        g: &SE3,
        mu: &SVector<f64, 6>,
    ) -> Option<SVector<f64, 6>> {
        each_motion!(self, s => s.velocity_from_momentum(t, g, mu))
    }
    fn is_forced(&self) -> bool {
        each_motion!(self, s => s.is_forced())
    }
    fn force<T: RealField + Copy>(&self, t: f64, g: &SE3<T>, xi: &SVector<T, 6>) -> SVector<T, 6> {
        each_motion!(self, s => s.force(t, g, xi))
    }
    fn force_jet(&self, t: f64, g: &SE3, xi: &SVector<f64, 6>) -> ForceJet<6> {
        each_motion!(self, s => s.force_jet(t, g, xi))
    }
    fn force_depends_on_configuration(&self) -> bool {
        each_motion!(self, s => s.force_depends_on_configuration())
    }
    fn momentum_derivatives(
        &self,
        t: f64,
        g: &SE3,
        xi: &SVector<f64, 6>,
    ) -> Option<(SMatrix<f64, 6, 6>, SMatrix<f64, 6, 6>)> {
        each_motion!(self, s => s.momentum_derivatives(t, g, xi))
    }
    fn local_derivatives(
        &self,
        t: f64,
        g: &SE3,
        xi: &SVector<f64, 6>,
        with_hessian: bool,
    ) -> Option<LocalDerivatives<6>> {
        each_motion!(self, s => s.local_derivatives(t, g, xi, with_hessian))
    }
    fn point_derivatives<C: GroupChart<RigidMotions, 6>>(
        &self,
        chart: &C,
        point: &GaussPoint<'_, RigidMotions, 6>,
        out: &mut <RigidMotions as StepGroup<6>>::Jet,
    ) -> bool {
        each_motion!(self, s => s.point_derivatives(chart, point, out))
    }
    fn motion_rate(&self, t: f64, g: &SE3, xi: &SVector<f64, 6>) -> f64 {
        match self {
            BuiltInSe3::Free(s) => s.motion_rate(t, g, xi),
            BuiltInSe3::Orbit(s) => s.motion_rate(t, g, xi),
        }
    }
    fn model_breakdown(&self, t: f64, g: &SE3, xi: &SVector<f64, 6>) -> Option<String> {
        each_motion!(self, s => s.model_breakdown(t, g, xi))
    }
    fn flow_guess<C: GroupChart<RigidMotions, 6>>(
        &self,
        chart: &C,
        start: &FlowStart<'_, RigidMotions, 6>,
        out: &mut [SVector<f64, 6>],
    ) -> FlowGuess<SE3> {
        each_motion!(self, s => s.flow_guess(chart, start, out))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::SO3;
    use crate::{Inertia, Integrator, StepSettings};
    use nalgebra::Vector3;

    /// Runs `system` 25 steps from a start in orbit (its perigee, near t = 15, stays
    /// outside twice the body's radius of gyration) and returns the final state's
    /// configuration entries and the Newton work.
    fn run<S: System<6, Group = RigidMotions>>(system: S) -> (Vec<f64>, usize, usize) {
        let start = SE3::new(SO3::identity(), Vector3::new(3.0, 0.0, 0.0));
        let mut velocity = SVector::<f64, 6>::zeros();
        velocity.copy_from_slice(&[0.6, 0.1, -0.4, 0.0, 0.55, 0.05]);
        let mut it =
            Integrator::new(system, StepSettings::new(1.0, 8).unwrap(), start, velocity).unwrap();
        for _ in 0..25 {
            it.step().unwrap();
        }
        let g = it.state().configuration;
        let entries = g
            .rotation()
            .matrix()
            .iter()
            .chain(g.translation().iter())
            .copied();
        let stats = it.statistics();
        (
            entries.collect(),
            stats.newton_iterations,
            stats.factorizations,
        )
    }

    #[test]
    fn the_motions_take_the_bodies_own_closed_forms() {
        // Bit for bit the body's own run, Newton's work included: a method left to its
        // default (ℓ's derivatives by dual numbers, no flow predictor) rounds differently
        // and takes other iterations.
        let inertia = Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap();
        let orbit = OrbitingBody::new(inertia, 1.0, 1.0).unwrap();
        assert_eq!(run(BuiltInSe3::Orbit(orbit)), run(orbit));
        let free = FreeBody::new(inertia, 2.0).unwrap();
        assert_eq!(run(BuiltInSe3::Free(free)), run(free));
        // The diagnosis of a failed step too: the attracting point within the body's mass, and not.
        for x in [0.5, 3.0] {
            let g = SE3::new(SO3::identity(), Vector3::new(x, 0.0, 0.0));
            let v = SVector::<f64, 6>::zeros();
            let own = orbit.model_breakdown(0.0, &g, &v);
            assert_eq!(own.is_some(), x < 1.0);
            assert_eq!(BuiltInSe3::Orbit(orbit).model_breakdown(0.0, &g, &v), own);
        }
    }
}
