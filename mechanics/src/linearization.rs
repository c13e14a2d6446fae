//! The exact linearisation of a step: `A = ∂x₊/∂x` and `B = ∂x₊/∂u` for control loops
//! (LQR, MPC, iLQR, an EKF), from [`crate::Integrator::linearize`] and
//! [`crate::Integrator::step_linearized`].
//!
//! # Coordinates
//! The state perturbation is taken in the body frame of the step's start and end
//! states:
//! - the configuration by `g = ḡ exp(θ)` (on SO(3), `R = R̄ exp(θ̂)`);
//! - [`Coordinates::Velocity`]: the body velocity by `ξ = ξ̄ + ω` (on SO(3), `Ω = Ω̄ + ω`);
//! - [`Coordinates::Momentum`]: the body momentum by `μ = μ̄ + δμ`.
//!
//! The state vector is `(θ, ω)` or `(θ, δμ)` (`2D` entries, in the algebra's order: on
//! SE(3) `θ = (θ_R, θ_x)`, `ω = (δΩ, δv)`). The input is the control input of
//! [`crate::Integrator::set_input`] (a body torque on SO(3), a body wrench `(τ, f)` on
//! SE(3)), held over the step; `B` is its derivative at the input in force, so a
//! linearisation at zero input is the right one for a loop that adds `u` to nothing.
//! For a body in space, [`StepLinearization::world_frame`] gives the same step in
//! `(θ_R, δx, δΩ, δẋ)` with the position and its velocity in the world frame.
//!
//! # Parameters
//! [`crate::Integrator::linearize_with_parameters`] and
//! [`crate::Integrator::step_linearized_with_parameters`] add `P = ∂x₊/∂p`
//! ([`StepLinearization::p`]) in the system's physical parameters
//! ([`crate::System::parameter_names`]: the inertia tensor's entries, the mass, an
//! orbiting body's gravitational parameter or the wheels' inertias), so that `x₊ ≈ A x + B u + P δp`: for sensitivity studies and
//! for estimating the parameters from measured motion (the `inertia_estimation` example).
//!
//! # How it is computed
//! A step solves `F(Ξ; θ, μ_k, u) = 0`, so by the implicit function theorem
//! `∂Ξ/∂(θ, μ_k, u) = −F_Ξ⁻¹ F_{(θ, μ, u)}`, with the exact Newton matrix assembled and
//! factored afresh at the converged step (never the chord iteration's kept factor), and
//! the end state's dependence on `Ξ` in closed form. Exact to rounding: no finite
//! differences. The velocity coordinates follow from the momentum ones through the
//! Legendre transform at each end, `δμ = L_ξη θ + L_ξξ ω` with `L(η, ξ) = ℓ(t, g exp(η), ξ)`.
//! The derivation is in `docs/notes/linearization.md`.

use crate::error::MechanicsError;
use crate::group::{ConfigurationGroup, StepGroup};
use crate::state::{body_momentum, legendre_blocks, State};
use crate::step::linearize::{
    MomentumJacobians, ParameterDerivative, ParameterJacobians, PointInputJacobians,
};
use crate::system::System;
use lgsvi_lie::{LieGroup, SE3};
use nalgebra::{DMatrix, Matrix3, SMatrix, SVector};

/// The coordinates of a step's state perturbation (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Coordinates {
    /// `(θ, ω)`: attitude (and position) in the body frame, body velocity.
    #[default]
    Velocity,
    /// `(θ, δμ)`: attitude (and position) in the body frame, body momentum; the
    /// coordinates in which a conservative step's `A` is symplectic for the
    /// left-trivialised form ([`StepLinearization::symplectic_form`]).
    Momentum,
}

/// The exact linearisation of one step (module documentation): `x₊ ≈ A x + B u`.
#[derive(Debug, Clone)]
pub struct StepLinearization<E, const D: usize> {
    /// The state the step starts from.
    pub start: State<E, D>,
    /// The state the step ends at.
    pub end: State<E, D>,
    /// The control input held over the step (the point of linearisation in `u`).
    pub input: SVector<f64, D>,
    /// The step `h`.
    pub h: f64,
    /// The nodes of the step.
    pub nodes: usize,
    a_momentum: DMatrix<f64>,
    b_momentum: DMatrix<f64>,
    a_velocity: DMatrix<f64>,
    b_velocity: DMatrix<f64>,
    parameters: Option<ParameterColumns>,
    points: Option<PointColumns>,
    configurations: PointColumns,
}

/// `∂x₊/∂u_j` per Gauss point in both coordinates (or, for the configurations at the
/// points, `∂θ_j/∂(x, u)`).
#[derive(Debug, Clone)]
struct PointColumns {
    momentum: Vec<DMatrix<f64>>,
    velocity: Vec<DMatrix<f64>>,
}

/// `∂x₊/∂p` in both coordinates, with the parameters' names.
#[derive(Debug, Clone)]
struct ParameterColumns {
    names: Vec<String>,
    momentum: DMatrix<f64>,
    velocity: DMatrix<f64>,
}

impl<E, const D: usize> StepLinearization<E, D> {
    /// `A = ∂x₊/∂x` (`2D × 2D`) in `coordinates`.
    pub fn a(&self, coordinates: Coordinates) -> &DMatrix<f64> {
        match coordinates {
            Coordinates::Velocity => &self.a_velocity,
            Coordinates::Momentum => &self.a_momentum,
        }
    }

    /// `B = ∂x₊/∂u` (`2D × D`) in `coordinates`.
    pub fn b(&self, coordinates: Coordinates) -> &DMatrix<f64> {
        match coordinates {
            Coordinates::Velocity => &self.b_velocity,
            Coordinates::Momentum => &self.b_momentum,
        }
    }

    /// `B_j = ∂x₊/∂u_j` (`2D × D` each) in `coordinates`, one per Gauss point of the
    /// step: the derivative in the input at point `j` when the inputs were given per point
    /// ([`crate::Integrator::set_input_at_points`]; `None` for a constant input). They sum
    /// to [`StepLinearization::b`], the derivative in an input added at every point.
    pub fn b_points(&self, coordinates: Coordinates) -> Option<&[DMatrix<f64>]> {
        self.points.as_ref().map(|p| match coordinates {
            Coordinates::Velocity => p.velocity.as_slice(),
            Coordinates::Momentum => p.momentum.as_slice(),
        })
    }

    /// The configuration at each Gauss point of the step and its derivative in the start
    /// and the input: the step's curve passes through `g_j = g(t + c_j h)` at the step's
    /// Gauss points ([`crate::Integrator::quadrature_nodes`]), and a perturbation moves it to
    /// `g_j exp(θ_j)` (in the body frame at the point, as the end state's `θ₊`). Matrix `j`
    /// is `∂θ_j/∂(x, u)`, `D` rows: `2D` columns in the start state in `coordinates`, then
    /// the input's `D` (held over the step), or `D` per Gauss point in the order of the
    /// points (inputs at the points, [`crate::Integrator::set_input_at_points`]).
    ///
    /// What a cost or a constraint on the motion within a step differentiates by (a
    /// body-frame force's direction in the world, a pointing constraint at the points);
    /// `θ₊`'s rows of `A` and `B` are the same derivative at the step's end.
    pub fn point_configurations(&self, coordinates: Coordinates) -> &[DMatrix<f64>] {
        match coordinates {
            Coordinates::Velocity => &self.configurations.velocity,
            Coordinates::Momentum => &self.configurations.momentum,
        }
    }

    /// `∂x₊/∂p` (`2D × P`) in `coordinates`: the end state's derivative in the system's
    /// physical parameters ([`StepLinearization::parameter_names`], one column each), with
    /// the start state held in those coordinates (in [`Coordinates::Velocity`] the start's
    /// velocity is held and its momentum moves with the parameters; in
    /// [`Coordinates::Momentum`] its momentum is held). `None` unless the linearisation
    /// was asked for with the parameters
    /// ([`crate::Integrator::linearize_with_parameters`],
    /// [`crate::Integrator::step_linearized_with_parameters`]).
    pub fn p(&self, coordinates: Coordinates) -> Option<&DMatrix<f64>> {
        self.parameters.as_ref().map(|p| match coordinates {
            Coordinates::Velocity => &p.velocity,
            Coordinates::Momentum => &p.momentum,
        })
    }

    /// The names of the columns of [`StepLinearization::p`] (empty when it is `None`, or
    /// for a system without parameters): for the built-in bodies
    /// [`crate::inertia::INERTIA_PARAMETERS`], then the mass where `ℓ` has one (the gyrostat: its
    /// wheels' inertias `I_1 … I_K`; the orbiting body: then its gravitational parameter
    /// `mu`).
    pub fn parameter_names(&self) -> &[String] {
        self.parameters.as_ref().map_or(&[], |p| &p.names)
    }
}

impl<E: Copy, const D: usize> StepLinearization<E, D> {
    /// The left-trivialised symplectic form of `T*G` at body momentum `μ`, in momentum
    /// coordinates: `ω(z₁, z₂) = z₁ᵀ W z₂` with `W = [[−C(μ)ᵀ, −I], [I, 0]]`,
    /// `C(μ)η = ad_ηᵀ μ` (the derivative of the canonical one-form `⟨μ, g⁻¹δg⟩`). A
    /// conservative step satisfies `Aᵀ W(μ₊) A = W(μ)` ([`Coordinates::Momentum`]).
    pub fn symplectic_form<G: StepGroup<D>>(momentum: &SVector<f64, D>) -> DMatrix<f64> {
        let c = G::coadjoint_generator(momentum);
        let mut w = DMatrix::zeros(2 * D, 2 * D);
        for r in 0..D {
            for col in 0..D {
                w[(r, col)] = -c[(col, r)];
            }
            w[(r, D + r)] = -1.0;
            w[(D + r, r)] = 1.0;
        }
        w
    }

    /// Builds the linearisation from the step's momentum Jacobians and the Legendre
    /// transforms at both ends.
    #[allow(clippy::too_many_arguments)] // the step's parts, each from its own computation
    pub(crate) fn new<S>(
        system: &S,
        jacobians: &MomentumJacobians<D>,
        start: State<E, D>,
        end: State<E, D>,
        input: SVector<f64, D>,
        (h, nodes, index): (f64, usize, usize),
        parameters: Option<ParameterJacobians>,
        points: Option<PointInputJacobians<D>>,
    ) -> Result<Self, MechanicsError>
    where
        S: System<D>,
        S::Group: ConfigurationGroup<D, Element<f64> = E>,
    {
        let j = jacobians;
        let a_momentum = blocks(&j.theta_theta, &j.theta_mu, &j.mu_theta, &j.mu_mu);
        let b_momentum = stacked(&j.theta_u, &j.mu_u);
        // x_μ = T x_ω with T = [[I, 0], [P, Q]] (P = L_ξη, Q = L_ξξ) at each end, so that
        // A_ω = T_out⁻¹ A_μ T_in and B_ω = T_out⁻¹ B_μ with T_out⁻¹ = [[I, 0], [−Q⁻¹P, Q⁻¹]],
        // formed by D × D blocks.
        let (p_in, q_in) =
            legendre_blocks(system, start.time, &start.configuration, &start.velocity);
        let (p_out, q_out) = legendre_blocks(system, end.time, &end.configuration, &end.velocity);
        // A Lagrangian whose velocity Hessian is singular at the end has no velocity
        // coordinates there (a valid inertia never does): the Lagrangian's fault, named as
        // such with the Hessian's eigenvalues.
        let q_out_inverse = q_out.try_inverse().ok_or_else(|| {
            let eigenvalues =
                DMatrix::from_iterator(D, D, q_out.iter().copied()).symmetric_eigenvalues();
            MechanicsError::DegenerateLagrangian {
                step: index,
                time: end.time,
                least: eigenvalues.min(),
                most: eigenvalues.amax(),
            }
        })?;
        // A_μ T_in = [[x11, x12], [x21, x22]].
        let x11 = j.theta_theta + j.theta_mu * p_in;
        let x12 = j.theta_mu * q_in;
        let x21 = j.mu_theta + j.mu_mu * p_in;
        let x22 = j.mu_mu * q_in;
        let a_velocity = blocks(
            &x11,
            &x12,
            &(q_out_inverse * (x21 - p_out * x11)),
            &(q_out_inverse * (x22 - p_out * x12)),
        );
        let b_velocity = stacked(&j.theta_u, &(q_out_inverse * (j.mu_u - p_out * j.theta_u)));
        // The parameters: in velocity coordinates the start's momentum moves by
        // `M_in δp` (`M = ∂μ/∂p = ∂(∂ℓ/∂p)/∂ξ`), and the end's velocity by
        // `Q_out⁻¹(δμ₊ − P_out θ₊ − M_out δp)`.
        let parameters = parameters.map(|columns| {
            let names = columns.names;
            let m_in = parameter_momenta(system, &start, names.len());
            let m_out = parameter_momenta(system, &end, names.len());
            let theta = &columns.theta + j.theta_mu * &m_in;
            let mu = &columns.mu + j.mu_mu * &m_in;
            let omega = q_out_inverse * (mu - p_out * &theta - m_out);
            let mut momentum = DMatrix::zeros(2 * D, names.len());
            momentum.rows_mut(0, D).copy_from(&columns.theta);
            momentum.rows_mut(D, D).copy_from(&columns.mu);
            let mut velocity = DMatrix::zeros(2 * D, names.len());
            velocity.rows_mut(0, D).copy_from(&theta);
            velocity.rows_mut(D, D).copy_from(&omega);
            ParameterColumns {
                names,
                momentum,
                velocity,
            }
        });
        // The configurations at the points: the start's columns as A's, the input's
        // (held or at each point) as they are (the start is held in either coordinates).
        let inputs = points.as_ref().map_or(1, Vec::len);
        let (momentum, velocity) = j
            .points
            .iter()
            .enumerate()
            .map(|(q, [theta, mu, u])| {
                let mut momentum = DMatrix::zeros(D, (2 + inputs) * D);
                momentum.view_mut((0, 0), (D, D)).copy_from(theta);
                momentum.view_mut((0, D), (D, D)).copy_from(mu);
                match &points {
                    Some(columns) => {
                        for (i, column) in columns.iter().enumerate() {
                            momentum
                                .view_mut((0, (2 + i) * D), (D, D))
                                .copy_from(&column.configurations[q]);
                        }
                    }
                    None => momentum.view_mut((0, 2 * D), (D, D)).copy_from(u),
                }
                let mut velocity = momentum.clone();
                velocity
                    .view_mut((0, 0), (D, D))
                    .copy_from(&(theta + mu * p_in));
                velocity.view_mut((0, D), (D, D)).copy_from(&(mu * q_in));
                (momentum, velocity)
            })
            .unzip();
        let configurations = PointColumns { momentum, velocity };
        let points = points.map(|columns| {
            let (momentum, velocity) = columns
                .iter()
                .map(|column| {
                    let (theta, mu) = (&column.theta, &column.mu);
                    (
                        stacked(theta, mu),
                        stacked(theta, &(q_out_inverse * (mu - p_out * theta))),
                    )
                })
                .unzip();
            PointColumns { momentum, velocity }
        });
        Ok(Self {
            start,
            end,
            input,
            h,
            nodes,
            a_momentum,
            b_momentum,
            a_velocity,
            b_velocity,
            parameters,
            points,
            configurations,
        })
    }
}

/// `∂μ/∂p_k` at a state, one column a parameter: the Legendre transform of
/// [`System::parameter_lagrangian`] (dual numbers).
fn parameter_momenta<S, E, const D: usize>(
    system: &S,
    state: &State<E, D>,
    count: usize,
) -> DMatrix<f64>
where
    S: System<D>,
    S::Group: ConfigurationGroup<D, Element<f64> = E>,
{
    let mut m = DMatrix::zeros(D, count);
    for index in 0..count {
        let derivative = ParameterDerivative { system, index };
        m.set_column(
            index,
            &body_momentum(
                &derivative,
                state.time,
                &state.configuration,
                &state.velocity,
            ),
        );
    }
    m
}

impl StepLinearization<SE3, 6> {
    /// A body in space in world coordinates: `(A, B)` for the state `(θ_R, δx, δΩ, δẋ)`
    /// (12 entries) — the attitude perturbation `R = R̄ exp(θ̂_R)` and the body angular
    /// velocity as in [`Coordinates::Velocity`], the position `x` and its velocity `ẋ`
    /// in the world frame. The input stays the body wrench `(τ, f)`.
    ///
    /// From `g exp(θ) = (R(I + θ̂_R), x + R θ_x)` to first order and `ẋ = R v`:
    /// `δx = R θ_x`, `δẋ = R (δv − v̂ θ_R)`.
    pub fn world_frame(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        let p_in_inverse = world_from_body(&self.start.configuration, &self.start.velocity, true);
        let p_out = world_from_body(&self.end.configuration, &self.end.velocity, false);
        (
            &p_out * &self.a_velocity * p_in_inverse,
            &p_out * &self.b_velocity,
        )
    }

    /// [`StepLinearization::p`] in the world-frame coordinates of
    /// [`StepLinearization::world_frame`]: `∂(θ_R, x, Ω, ẋ)₊/∂p` (12 × P), `None` as `p`.
    pub fn world_frame_parameters(&self) -> Option<DMatrix<f64>> {
        let p_out = world_from_body(&self.end.configuration, &self.end.velocity, false);
        self.p(Coordinates::Velocity).map(|p| &p_out * p)
    }
}

/// The map `P` from a body in space's state perturbation in the native coordinates
/// `(θ_R, θ_x, δΩ, δv)` ([`Coordinates::Velocity`]) to the world frame's
/// `(θ_R, δx, δΩ, δẋ)` at the state `(g, ξ)`: `δx = R θ_x`, `δẋ = R (δv − v̂ θ_R)`. What
/// [`StepLinearization::world_frame`] applies at a step's end; for a sensitivity chained
/// over many steps (`P ∂x_K/∂u` at the last state), or a state's own.
///
/// ```
/// use lgsvi_mechanics::linearization::world_coordinates;
/// use lgsvi_mechanics::lie::{SE3, SO3};
/// use nalgebra::{SVector, Vector3};
/// // Turned a quarter about z: a body-frame position perturbation along x is along y.
/// let g = SE3::new(SO3::exp(&Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2)), Vector3::zeros());
/// let p = world_coordinates(&g, &SVector::<f64, 6>::zeros());
/// assert!((p[(4, 3)] - 1.0).abs() < 1e-15);
/// ```
pub fn world_coordinates(configuration: &SE3, velocity: &SVector<f64, 6>) -> DMatrix<f64> {
    world_from_body(configuration, velocity, false)
}

/// `(θ_R, δx, δΩ, δẋ) = P (θ_R, θ_x, δΩ, δv)` at `(R, x)` with body velocity `(Ω, v)`
/// (`δx = R θ_x`, `δẋ = R(δv − v̂ θ_R)`), or with `inverse` its inverse
/// (`θ_x = Rᵀ δx`, `δv = Rᵀ δẋ + v̂ θ_R`).
fn world_from_body(g: &SE3, velocity: &SVector<f64, 6>, inverse: bool) -> DMatrix<f64> {
    let mut r: Matrix3<f64> = g.rotation().to_matrix();
    let v_hat = lgsvi_lie::so3::hat(&velocity.fixed_rows::<3>(3).into_owned());
    let coupling = if inverse {
        r = r.transpose();
        v_hat
    } else {
        -r * v_hat
    };
    let mut p = DMatrix::zeros(12, 12);
    p.view_mut((0, 0), (3, 3)).copy_from(&Matrix3::identity());
    p.view_mut((3, 3), (3, 3)).copy_from(&r);
    p.view_mut((6, 6), (3, 3)).copy_from(&Matrix3::identity());
    p.view_mut((9, 9), (3, 3)).copy_from(&r);
    p.view_mut((9, 0), (3, 3)).copy_from(&coupling);
    p
}

/// `[[a], [b]]` of `D × D` blocks.
fn stacked<const D: usize>(a: &SMatrix<f64, D, D>, b: &SMatrix<f64, D, D>) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(2 * D, D);
    m.view_mut((0, 0), (D, D)).copy_from(a);
    m.view_mut((D, 0), (D, D)).copy_from(b);
    m
}

/// `[[a, b], [c, d]]` of `D × D` blocks.
fn blocks<const D: usize>(
    a: &SMatrix<f64, D, D>,
    b: &SMatrix<f64, D, D>,
    c: &SMatrix<f64, D, D>,
    d: &SMatrix<f64, D, D>,
) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(2 * D, 2 * D);
    m.view_mut((0, 0), (D, D)).copy_from(a);
    m.view_mut((0, D), (D, D)).copy_from(b);
    m.view_mut((D, 0), (D, D)).copy_from(c);
    m.view_mut((D, D), (D, D)).copy_from(d);
    m
}
