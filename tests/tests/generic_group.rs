//! A group and a chart of the user's own reach the integrator unchanged: the torus
//! `T² = SO(2) × SO(2)` (angles `(θ₁, θ₂)`, abelian, `D = 2`) with its identity chart, and
//! on it the planar double pendulum (unit masses and lengths), whose mass matrix depends
//! on the configuration. This file is what a user writes to add a group.
//!
//! Reference: the pendulum's textbook equations of motion integrated by classical RK4 at
//! a step of 1e-4 (an independent route: it shares no code with lgsvi; its error at
//! T = 2 is ~(1e-4)⁴·T·|f⁽⁵⁾| ≈ 1e-14).

use lgsvi_lie::laws::{configuration_group_laws, group_chart_laws, group_laws};
use lgsvi_lie::{ConfigurationGroup, ExponentialMap, GroupChart, LieError, LieGroup};
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{Integrator, StepSettings, System};
use nalgebra::{RealField, SMatrix, SVector, Vector2};

/// A point of the torus, `(θ₁, θ₂)` (not reduced mod 2π: the chart is global).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Angles<T: RealField + Copy>(Vector2<T>);

impl<T: RealField + Copy> LieGroup for Angles<T> {
    type Scalar = T;
    type Tangent = Vector2<T>;
    type Jacobian = SMatrix<T, 2, 2>;
    type Point = Vector2<T>;
    type Matrix = Vector2<T>;
    const DOF: usize = 2;
    const NAME: &'static str = "T²";
    fn identity() -> Self {
        Angles(Vector2::zeros())
    }
    fn compose(&self, other: &Self) -> Self {
        Angles(self.0 + other.0)
    }
    fn inverse(&self) -> Self {
        Angles(-self.0)
    }
    fn act(&self, point: &Vector2<T>) -> Vector2<T> {
        point + self.0
    }
    fn to_matrix(&self) -> Vector2<T> {
        self.0
    }
    fn hat(xi: &Vector2<T>) -> Vector2<T> {
        *xi
    }
    fn vee(matrix: &Vector2<T>) -> Vector2<T> {
        *matrix
    }
    fn adjoint(&self) -> SMatrix<T, 2, 2> {
        SMatrix::identity()
    }
    fn small_adjoint(_xi: &Vector2<T>) -> SMatrix<T, 2, 2> {
        SMatrix::zeros()
    }
    fn coadjoint_action(&self, mu: &Vector2<T>) -> Vector2<T> {
        *mu
    }
}

/// The torus's exponential map is the identity on the angles.
impl<T: RealField + Copy> ExponentialMap for Angles<T> {
    fn exp(xi: &Vector2<T>) -> Self {
        Angles(*xi)
    }
    fn log(&self) -> Vector2<T> {
        self.0
    }
}

/// The marker type of the group.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Torus;

impl ConfigurationGroup<2> for Torus {
    type Element<T: RealField + Copy> = Angles<T>;
    const NAME: &'static str = "T²";
    fn lift<T: RealField + Copy>(g: &Angles<f64>) -> Angles<T> {
        Angles(g.0.map(nalgebra::convert))
    }
    fn exp<T: RealField + Copy>(zeta: &Vector2<T>) -> Angles<T> {
        Angles(*zeta)
    }
    fn is_finite(g: &Angles<f64>) -> bool {
        g.0.iter().all(|x| x.is_finite())
    }
    // The rest has defaults that fit an abelian group without rotation: no rotation angle
    // or angular speed to check a step against, nothing to renormalise, and the coadjoint
    // generator from `small_adjoint` (zero here).
}

/// The identity chart `Φ(ξ) = ξ`, `A = I`.
#[derive(Debug, Clone, Copy)]
struct AngleChart;

impl GroupChart<Torus, 2> for AngleChart {
    fn name(&self) -> &'static str {
        "angles"
    }
    fn to_group<T: RealField + Copy>(&self, xi: &Vector2<T>) -> Angles<T> {
        Angles(*xi)
    }
    fn left_differential<T: RealField + Copy>(&self, _xi: &Vector2<T>) -> SMatrix<T, 2, 2> {
        SMatrix::identity()
    }
    fn left_differential_inverse(
        &self,
        _xi: &Vector2<f64>,
    ) -> Result<SMatrix<f64, 2, 2>, LieError> {
        Ok(SMatrix::identity())
    }
    fn to_algebra_near(
        &self,
        g: &Angles<f64>,
        _near: &Vector2<f64>,
    ) -> Result<Vector2<f64>, LieError> {
        Ok(g.0)
    }
    // The domain check (every finite ξ) and the reach (no rotation: unbounded) are the
    // defaults.
}

const G: f64 = 9.81;

/// The double pendulum: `ℓ = ω₁² + ½ω₂² + ω₁ω₂ cos(θ₁ − θ₂) + 2g cos θ₁ + g cos θ₂`.
struct DoublePendulum;

impl System<2> for DoublePendulum {
    type Group = Torus;
    fn lagrangian<T: RealField + Copy>(&self, _t: f64, g: &Angles<T>, w: &Vector2<T>) -> T {
        let c = |x: f64| -> T { nalgebra::convert(x) };
        let (a, b) = (g.0.x, g.0.y);
        w.x * w.x
            + c(0.5) * w.y * w.y
            + w.x * w.y * (a - b).cos()
            + c(2.0 * G) * a.cos()
            + c(G) * b.cos()
    }
}

/// The textbook equations of motion (m = l = 1).
fn rate(s: &[f64; 4]) -> [f64; 4] {
    let [a, b, wa, wb] = *s;
    let d = a - b;
    let den = 3.0 - (2.0 * d).cos();
    let alpha = (-3.0 * G * a.sin()
        - G * (a - 2.0 * b).sin()
        - 2.0 * d.sin() * (wb * wb + wa * wa * d.cos()))
        / den;
    let beta = 2.0 * d.sin() * (2.0 * wa * wa + 2.0 * G * a.cos() + wb * wb * d.cos()) / den;
    [wa, wb, alpha, beta]
}

fn rk4(mut s: [f64; 4], t: f64, h: f64) -> [f64; 4] {
    let steps = (t / h).round() as usize;
    let add = |s: &[f64; 4], k: &[f64; 4], c: f64| std::array::from_fn(|i| s[i] + c * k[i]);
    for _ in 0..steps {
        let k1 = rate(&s);
        let k2 = rate(&add(&s, &k1, 0.5 * h));
        let k3 = rate(&add(&s, &k2, 0.5 * h));
        let k4 = rate(&add(&s, &k3, h));
        s = std::array::from_fn(|i| s[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    s
}

#[test]
fn a_users_own_group_and_chart_reach_the_integrator() {
    let (a0, b0, wa0, wb0) = (1.0, -0.5, 0.3, 0.0);
    let mut it = Integrator::with_chart(
        DoublePendulum,
        AngleChart,
        StepSettings::new(0.05, 10).unwrap(),
        Angles(Vector2::new(a0, b0)),
        SVector::<f64, 2>::new(wa0, wb0),
    )
    .unwrap();
    let e0 = it.state().energy(&DoublePendulum);
    it.run_until(2.0, 40).unwrap();
    let s = it.state();
    let reference = rk4([a0, b0, wa0, wb0], 2.0, 1e-4);
    let error = (s.configuration.0 - Vector2::new(reference[0], reference[1]))
        .amax()
        .max((s.velocity - Vector2::new(reference[2], reference[3])).amax());
    // A smooth, non-chaotic 2 s at h = 0.05, n = 10: the method's error is far below the
    // reference's; 1e-10 leaves room for the reference's and the rounding's.
    assert!(error < 1e-10, "error {error:e}");
    assert!((s.energy(&DoublePendulum) - e0).abs() < 1e-12 * e0.abs().max(1.0));
}

/// A user's group and chart run the law suite every group and chart run, with their own
/// examples: the torus is abelian with `exp` the identity on the angles, so every law holds
/// to rounding except those that difference (`ad` from `Ad`, the chart's differentials),
/// which the suite holds to its central-difference allowance.
#[test]
fn the_torus_passes_the_law_suite() {
    let tangents = [
        Vector2::new(0.3, -1.2),
        Vector2::new(2.0, 0.5),
        Vector2::new(-0.7, 0.1),
    ];
    let elements: Vec<Angles<f64>> = tangents.iter().map(Angles::exp).collect();
    let report = group_laws(&elements, &tangents, 16.0 * f64::EPSILON).unwrap();
    assert!(report
        .iter()
        .all(|(_, error)| *error <= 16.0 * f64::EPSILON * 2.0));
    configuration_group_laws::<Torus, 2>(&elements, &tangents, 16.0 * f64::EPSILON).unwrap();
    // The identity chart keeps every default, so its consistency laws compare the dual
    // numbers with themselves; the differentials against central differences are the test.
    let chart =
        group_chart_laws::<Torus, _, 2>(&AngleChart, &tangents, 16.0 * f64::EPSILON).unwrap();
    assert!(chart.iter().any(|(law, _)| *law == "left differential"));
}
