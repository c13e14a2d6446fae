//! Discrete LQR on the group, from the exact linearisation of a step
//! ([`crate::Integrator::linearize`]): the infinite-horizon gain at an equilibrium (the
//! discrete algebraic Riccati equation, [`dare`]), the finite-horizon time-varying gains
//! along a trajectory ([`finite_horizon_gains`]), and the small types a control loop
//! calls each step ([`Regulator`], [`TrajectoryTracker`]), with the error state taken by
//! the group's logarithm ([`GroupLog`]).
//!
//! Coordinates are those of [`crate::linearization::StepLinearization`] in [`crate::linearization::Coordinates::Velocity`]:
//! the error state of `(g, ξ)` against a reference `(ḡ, ξ̄)` is `(θ, ξ − ξ̄)` with
//! `g = ḡ exp(θ)`, and the input is the control input of [`crate::Integrator::set_input`].
//!
//! ```
//! use lgsvi_mechanics::control::{lqr, Regulator};
//! use lgsvi_mechanics::lie::SO3;
//! use lgsvi_mechanics::{HeavyTop, Inertia, Integrator, StepSettings};
//! use lgsvi_mechanics::linearization::Coordinates;
//! use nalgebra::{DMatrix, Vector3};
//!
//! // A 3D pendulum held upright: gravity pulls along −e₃, the centre of mass on +e₃.
//! let inertia = Inertia::from_principal_moments([1.0, 1.2, 0.8])?;
//! let top = HeavyTop::new(inertia, 1.0, 9.81, Vector3::z(), -Vector3::z())?;
//! let settings = StepSettings::new(0.05, 6)?;
//! let mut integrator = Integrator::new(top, settings, SO3::identity(), Vector3::zeros())?;
//! let upright = *integrator.state();
//! let step = integrator.linearize()?;
//! let (q, r) = (DMatrix::identity(6, 6), DMatrix::identity(3, 3) * 0.1);
//! let gain = lqr(step.a(Coordinates::Velocity), step.b(Coordinates::Velocity), &q, &r)?;
//! let regulator = Regulator::new(upright, Vector3::zeros(), gain.gain)?;
//! // Tilted by 0.1 rad, the loop brings it back.
//! integrator.reset(0.0, SO3::exp(&Vector3::new(0.1, 0.0, 0.0)), Vector3::zeros())?;
//! for _ in 0..200 {
//!     let u = regulator.input(integrator.state());
//!     integrator.set_input(u)?;
//!     integrator.step()?;
//! }
//! assert!(integrator.state().attitude().log().norm() < 1e-3);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::error::MechanicsError;
use crate::state::State;
use lgsvi_lie::{LieGroup, SE3, SO3};
use nalgebra::{DMatrix, DVector, SVector};

/// Doubling iterations allowed: the structured doubling algorithm converges
/// quadratically once it starts to (each iteration doubles the horizon it has summed), so
/// 60 iterations sum `2⁶⁰` steps of the Riccati recursion.
const MAX_DOUBLINGS: usize = 60;

/// The stabilising solution `P` of the discrete algebraic Riccati equation
/// `P = AᵀPA − AᵀPB (R + BᵀPB)⁻¹ BᵀPA + Q` (`A` `n × n`, `B` `n × m`, `Q` symmetric
/// positive semi-definite, `R` symmetric positive definite), by the structured doubling
/// algorithm (Chu, Fan & Lin, 2005): with `G = B R⁻¹ Bᵀ`,
/// `A ← A (I + G H)⁻¹ A`, `G ← G + A (I + G H)⁻¹ G Aᵀ`, `H ← H + Aᵀ H (I + G H)⁻¹ A`
/// from `H = Q`, whose `H` converges quadratically to `P` for a stabilisable `(A, B)` and
/// detectable `(A, Q)`.
///
/// # Errors
/// [`MechanicsError::InvalidSetting`] for sizes that do not match, a non-finite entry,
/// an `R` that is not positive definite, or a pair without a stabilising solution (the
/// doubling does not converge: the equilibrium cannot be stabilised by this input, or a
/// mode that `Q` does not see is unstable).
pub fn dare(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<DMatrix<f64>, MechanicsError> {
    check_sizes(a, b, q, r)?;
    let n = a.nrows();
    let r_inverse = r
        .clone()
        .cholesky()
        .ok_or_else(|| invalid("R", r, "must be symmetric positive definite"))?
        .inverse();
    let mut a_k = a.clone();
    let mut g = b * r_inverse * b.transpose();
    let mut h = q.clone();
    let identity = DMatrix::<f64>::identity(n, n);
    for _ in 0..MAX_DOUBLINGS {
        let w = (&identity + &g * &h)
            .lu()
            .try_inverse()
            .ok_or_else(|| invalid("A, B", a, "the doubling met a singular I + GH"))?;
        let a_w = &a_k * &w;
        let next_h = &h + a_k.transpose() * &h * &w * &a_k;
        let next_g = &g + &a_w * &g * a_k.transpose();
        let next_a = &a_w * &a_k;
        let change = (&next_h - &h).amax();
        h = symmetric(next_h);
        g = symmetric(next_g);
        a_k = next_a;
        if !h.iter().all(|x| x.is_finite()) {
            break;
        }
        // The change halves its exponent each iteration near the solution: below 1e-15
        // of P the next would change nothing.
        if change <= 1e-15 * h.amax().max(f64::MIN_POSITIVE) {
            return Ok(h);
        }
    }
    Err(invalid(
        "A, B",
        a,
        "the Riccati equation has no stabilising solution for this A, B, Q (an unstable mode \
         the input cannot reach, or one Q does not weigh)",
    ))
}

/// An LQR design: the gain `K` of `u = −K x` and the Riccati solution `P` it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct LqrGain {
    /// `K = (R + BᵀPB)⁻¹ BᵀPA` (`m × n`).
    pub gain: DMatrix<f64>,
    /// `P` (`n × n`), the cost-to-go `xᵀPx` of the closed loop.
    pub cost: DMatrix<f64>,
}

/// The infinite-horizon discrete LQR gain for `x₊ = A x + B u` with stage cost
/// `xᵀQx + uᵀRu`: `u = −K x` ([`dare`]).
///
/// # Errors
/// As [`dare`].
pub fn lqr(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<LqrGain, MechanicsError> {
    let p = dare(a, b, q, r)?;
    let gain = feedback(a, b, r, &p)?;
    Ok(LqrGain { gain, cost: p })
}

/// The time-varying gains `K_k` (`u_k = −K_k x_k`) of the finite-horizon LQR along a
/// trajectory with linearisations `(A_k, B_k)`, `k = 0..N`, stage cost `xᵀQx + uᵀRu` and
/// final cost `xᵀQ_f x`: the backward Riccati recursion `P_N = Q_f`,
/// `K_k = (R + B_kᵀP_{k+1}B_k)⁻¹ B_kᵀP_{k+1}A_k`, `P_k = Q + A_kᵀP_{k+1}(A_k − B_k K_k)`.
///
/// # Errors
/// As [`dare`] for sizes, entries and `R`.
pub fn finite_horizon_gains(
    steps: &[(DMatrix<f64>, DMatrix<f64>)],
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
    final_cost: &DMatrix<f64>,
) -> Result<Vec<DMatrix<f64>>, MechanicsError> {
    let mut p = final_cost.clone();
    let mut gains = vec![DMatrix::zeros(0, 0); steps.len()];
    for (k, (a, b)) in steps.iter().enumerate().rev() {
        check_sizes(a, b, q, r)?;
        if p.shape() != a.shape() {
            return Err(invalid("Q_f", &p, "must be n × n like A"));
        }
        let gain = feedback(a, b, r, &p)?;
        p = symmetric(q + a.transpose() * &p * (a - b * &gain));
        gains[k] = gain;
    }
    Ok(gains)
}

/// `(R + BᵀPB)⁻¹ BᵀPA`.
fn feedback(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    r: &DMatrix<f64>,
    p: &DMatrix<f64>,
) -> Result<DMatrix<f64>, MechanicsError> {
    let bt_p = b.transpose() * p;
    (r + &bt_p * b)
        .cholesky()
        .map(|c| c.solve(&(bt_p * a)))
        .ok_or_else(|| invalid("R", r, "R + BᵀPB is not positive definite: R must be"))
}

fn symmetric(m: DMatrix<f64>) -> DMatrix<f64> {
    (&m + m.transpose()) * 0.5
}

fn invalid(name: &'static str, value: &DMatrix<f64>, reason: &'static str) -> MechanicsError {
    MechanicsError::InvalidSetting {
        name,
        value: format!("{}×{} matrix", value.nrows(), value.ncols()),
        reason,
    }
}

fn check_sizes(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<(), MechanicsError> {
    let n = a.nrows();
    if a.ncols() != n || n == 0 {
        return Err(invalid("A", a, "must be square and not empty"));
    }
    if b.nrows() != n || b.ncols() == 0 {
        return Err(invalid(
            "B",
            b,
            "must have A's rows and at least one column",
        ));
    }
    if q.shape() != (n, n) {
        return Err(invalid("Q", q, "must be n × n like A"));
    }
    let m = b.ncols();
    if r.shape() != (m, m) {
        return Err(invalid("R", r, "must be m × m for B's m columns"));
    }
    for (name, matrix) in [("A", a), ("B", b), ("Q", q), ("R", r)] {
        if !matrix.iter().all(|x| x.is_finite()) {
            return Err(MechanicsError::NonFinite {
                what: name,
                value: format!("{matrix}"),
            });
        }
    }
    Ok(())
}

/// The group's logarithm as the error coordinates of a control loop: `θ` with
/// `g = reference · exp(θ)`, the coordinates of [`crate::linearization::StepLinearization`].
pub trait GroupLog<const D: usize>: Sized {
    /// `θ = log(reference⁻¹ g)`.
    fn log_from(&self, reference: &Self) -> SVector<f64, D>;
}

impl GroupLog<3> for SO3 {
    fn log_from(&self, reference: &Self) -> SVector<f64, 3> {
        reference.inverse().compose(self).log()
    }
}

impl GroupLog<6> for SE3 {
    fn log_from(&self, reference: &Self) -> SVector<f64, 6> {
        reference.inverse().compose(self).log()
    }
}

/// The error state `(θ, ξ − ξ̄)` (`2D` entries) of `state` against `reference`.
pub fn error_state<E: GroupLog<D>, const D: usize>(
    state: &State<E, D>,
    reference: &State<E, D>,
) -> DVector<f64> {
    let theta = state.configuration.log_from(&reference.configuration);
    let mut x = DVector::zeros(2 * D);
    x.rows_mut(0, D).copy_from(&theta);
    x.rows_mut(D, D)
        .copy_from(&(state.velocity - reference.velocity));
    x
}

/// `u = ū − K x` for a gain of the right shape.
fn control<const D: usize>(
    feedforward: &SVector<f64, D>,
    gain: &DMatrix<f64>,
    x: &DVector<f64>,
) -> SVector<f64, D> {
    let feedback = gain * x;
    SVector::<f64, D>::from_fn(|i, _| feedforward[i] - feedback[i])
}

fn check_gain<const D: usize>(gain: &DMatrix<f64>) -> Result<(), MechanicsError> {
    if gain.shape() != (D, 2 * D) {
        return Err(invalid(
            "K",
            gain,
            "must be D × 2D: one row per input, one column per state",
        ));
    }
    if !gain.iter().all(|x| x.is_finite()) {
        return Err(MechanicsError::NonFinite {
            what: "K",
            value: format!("{gain}"),
        });
    }
    Ok(())
}

/// A regulator about an equilibrium: `u = ū − K (θ, ξ − ξ̄)`, the error taken by the
/// group's logarithm ([`error_state`]), `K` from [`lqr`] on the equilibrium's
/// linearisation. Call [`Regulator::input`] each step and hand the result to
/// [`crate::Integrator::set_input`].
#[derive(Debug, Clone)]
pub struct Regulator<E, const D: usize> {
    reference: State<E, D>,
    feedforward: SVector<f64, D>,
    gain: DMatrix<f64>,
}

impl<E: GroupLog<D> + Copy, const D: usize> Regulator<E, D> {
    /// About `reference` (held by the input `feedforward`, zero at a free equilibrium)
    /// with the gain `K` (`D × 2D`).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for a gain of another shape,
    /// [`MechanicsError::NonFinite`] for a non-finite one.
    pub fn new(
        reference: State<E, D>,
        feedforward: SVector<f64, D>,
        gain: DMatrix<f64>,
    ) -> Result<Self, MechanicsError> {
        check_gain::<D>(&gain)?;
        Ok(Self {
            reference,
            feedforward,
            gain,
        })
    }

    /// The input for `state`.
    pub fn input(&self, state: &State<E, D>) -> SVector<f64, D> {
        control(
            &self.feedforward,
            &self.gain,
            &error_state(state, &self.reference),
        )
    }
}

/// A time-varying tracker along a trajectory: at step `k`,
/// `u_k = ū_k − K_k (θ, ξ − ξ̄_k)` against the reference state `k`, with the gains of
/// [`finite_horizon_gains`] on the reference's linearisations.
#[derive(Debug, Clone)]
pub struct TrajectoryTracker<E, const D: usize> {
    references: Vec<State<E, D>>,
    feedforward: Vec<SVector<f64, D>>,
    gains: Vec<DMatrix<f64>>,
}

impl<E: GroupLog<D> + Copy, const D: usize> TrajectoryTracker<E, D> {
    /// Along `references` (the state at the start of each step) with the inputs that
    /// drive them and one gain per step.
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for lists of different lengths or a gain of the
    /// wrong shape; [`MechanicsError::NonFinite`] for a non-finite gain.
    pub fn new(
        references: Vec<State<E, D>>,
        feedforward: Vec<SVector<f64, D>>,
        gains: Vec<DMatrix<f64>>,
    ) -> Result<Self, MechanicsError> {
        if references.len() != gains.len() || feedforward.len() != gains.len() {
            return Err(MechanicsError::InvalidSetting {
                name: "tracker",
                value: format!(
                    "{} states, {} inputs, {} gains",
                    references.len(),
                    feedforward.len(),
                    gains.len()
                ),
                reason: "one reference state, one input and one gain per step",
            });
        }
        for gain in &gains {
            check_gain::<D>(gain)?;
        }
        Ok(Self {
            references,
            feedforward,
            gains,
        })
    }

    /// The number of steps it tracks.
    pub fn len(&self) -> usize {
        self.gains.len()
    }

    /// Whether it tracks no step.
    pub fn is_empty(&self) -> bool {
        self.gains.is_empty()
    }

    /// The input at step `k` for `state`; `None` past the last step.
    pub fn input(&self, k: usize, state: &State<E, D>) -> Option<SVector<f64, D>> {
        let gain = self.gains.get(k)?;
        Some(control(
            &self.feedforward[k],
            gain,
            &error_state(state, &self.references[k]),
        ))
    }
}

/// A PD attitude law with a torque limit, for a controller that samples the state and
/// holds its torque (zero-order hold): `u = sat_L(−K θ − C Ω)` with `θ = log(R_targetᵀ R)`
/// (the rotation vector from the target to the attitude, as
/// [`crate::forces::AttitudeSpring::error`]) and `sat_L` scaling a torque longer than `L`
/// back to length `L` along its own direction (an actuator's torque limit that keeps the
/// law's axis).
///
/// Call [`PdLaw::torque`] with the state at each sampling instant and hand the torque to
/// [`crate::Integrator::set_input`]: the step's input is constant over the step, so the
/// solution is as smooth within a step as without control and the step keeps its
/// accuracy, saturated or not. The continuous law (acting at every Gauss point, without a
/// limit) is [`crate::forces::AttitudeSpring`] beside [`crate::forces::AngularDamping`].
///
/// ```
/// use lgsvi_mechanics::control::PdLaw;
/// use lgsvi_mechanics::lie::SO3;
/// use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
/// use nalgebra::Vector3;
///
/// // A quarter turn about z, at most 0.2 N·m of torque, sampled every 0.25 s.
/// let target = SO3::exp(&Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
/// let law = PdLaw::new(target, 1.0, 2.0)?.with_limit(0.2)?;
/// let body = RigidBody::new(Inertia::from_principal_moments([2.0, 3.0, 4.0])?);
/// let mut it = Integrator::new(body, StepSettings::new(0.25, 8)?, SO3::identity(), Vector3::zeros())?;
/// for _ in 0..200 {
///     let s = it.state();
///     let u = law.torque(&s.configuration, &s.velocity);
///     assert!(u.norm() <= 0.2 * (1.0 + 1e-15));
///     it.set_input(u)?;
///     it.step()?;
/// }
/// assert!(law.error_angle(&it.state().configuration) < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PdLaw {
    spring: crate::forces::AttitudeSpring,
    damping: f64,
    limit: f64,
}

impl PdLaw {
    /// The law of gain `K` (N·m per radian) and rate gain `C` (N·m·s per radian) toward
    /// `target`, without a torque limit.
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for a gain that is negative or not finite;
    /// [`MechanicsError::NonFinite`] for a target with an entry that is not finite.
    pub fn new(target: SO3, k: f64, c: f64) -> Result<Self, MechanicsError> {
        let spring = crate::forces::AttitudeSpring::new(target, k)?;
        if !(c.is_finite() && c >= 0.0) {
            return Err(MechanicsError::InvalidSetting {
                name: "C",
                value: format!("{c:?}"),
                reason: "the rate gain of −CΩ must be finite and non-negative",
            });
        }
        Ok(Self {
            spring,
            damping: c,
            limit: f64::INFINITY,
        })
    }

    /// The law with its torque's length limited to `limit` (N·m; `f64::INFINITY` for no
    /// limit).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for a limit that is not positive (or NaN).
    pub fn with_limit(mut self, limit: f64) -> Result<Self, MechanicsError> {
        if limit.is_nan() || limit <= 0.0 {
            return Err(MechanicsError::InvalidSetting {
                name: "torque limit",
                value: format!("{limit:?}"),
                reason: "the actuator's largest torque must be positive",
            });
        }
        self.limit = limit;
        Ok(self)
    }

    /// The target attitude.
    pub fn target(&self) -> &SO3 {
        self.spring.target()
    }

    /// The gain `K`.
    pub fn gain(&self) -> f64 {
        self.spring.stiffness()
    }

    /// The rate gain `C`.
    pub fn rate_gain(&self) -> f64 {
        self.damping
    }

    /// The torque limit `L` (`f64::INFINITY` without one).
    pub fn limit(&self) -> f64 {
        self.limit
    }

    /// The pointing error `|θ|`, radians, of `attitude` from the target.
    pub fn error_angle(&self, attitude: &SO3) -> f64 {
        self.spring.error(attitude).norm()
    }

    /// The torque `sat_L(−K θ − C Ω)` at the attitude `R` and body rate `Ω`.
    pub fn torque(&self, attitude: &SO3, rate: &nalgebra::Vector3<f64>) -> nalgebra::Vector3<f64> {
        let u = self.spring.torque(attitude) - self.damping * rate;
        let norm = u.norm();
        if norm > self.limit {
            u * (self.limit / norm)
        } else {
            u
        }
    }
}
