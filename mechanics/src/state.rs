//! The state of a run — time, configuration, body momentum and velocity — and the Legendre
//! transform between momentum and velocity, with its derivatives.

use crate::error::MechanicsError;
use crate::group::ConfigurationGroup;
use crate::system::{ElementOf, System};
use lgsvi_lie::{LieGroup, SE3, SO3};
use nalgebra::{SMatrix, SVector, Vector3};
use num_dual::{Dual2SVec64, DualSVec64, HyperDualSVec64};

/// `μ = ∂ℓ/∂ξ(t, g, ξ)` (the Legendre transform), by dual numbers.
pub fn body_momentum<S: System<D>, const D: usize>(
    system: &S,
    time: f64,
    configuration: &ElementOf<S, D>,
    velocity: &SVector<f64, D>,
) -> SVector<f64, D> {
    let (_, gradient) = num_dual::gradient(
        |w: SVector<DualSVec64<D>, D>| {
            let g = <S::Group as ConfigurationGroup<D>>::lift(configuration);
            system.lagrangian(time, &g, &w)
        },
        velocity,
    );
    gradient
}

/// `ξ` with `∂ℓ/∂ξ(t, g, ξ) = μ`: the closed form when the system has one, else Newton
/// with the exact Hessian `∂²ℓ/∂ξ²` from `guess`.
///
/// # Errors
/// [`MechanicsError::InverseLegendre`] if Newton does not converge (a Lagrangian not
/// strictly convex in `ξ`).
pub fn body_velocity<S: System<D>, const D: usize>(
    system: &S,
    time: f64,
    configuration: &ElementOf<S, D>,
    momentum: &SVector<f64, D>,
    guess: &SVector<f64, D>,
) -> Result<SVector<f64, D>, MechanicsError> {
    if let Some(velocity) = system.velocity_from_momentum(time, configuration, momentum) {
        return Ok(velocity);
    }
    let mut velocity = *guess;
    let mut residual_norm = f64::INFINITY;
    for iteration in 0..50 {
        let (_, gradient, hessian) = num_dual::hessian(
            |w: SVector<Dual2SVec64<D>, D>| {
                let g = <S::Group as ConfigurationGroup<D>>::lift(configuration);
                system.lagrangian(time, &g, &w)
            },
            &velocity,
        );
        let residual = gradient - momentum;
        residual_norm = residual.amax();
        if residual_norm <= 16.0 * f64::EPSILON * momentum.amax().max(1.0) {
            return Ok(velocity);
        }
        let Some(delta) = solve_small(hessian, residual) else {
            break;
        };
        velocity -= delta;
        if !velocity.iter().all(|w| w.is_finite()) {
            break;
        }
        if iteration > 0 && delta.amax() <= 4.0 * f64::EPSILON * velocity.amax() {
            return Ok(velocity);
        }
    }
    Err(MechanicsError::InverseLegendre {
        residual: residual_norm,
    })
}

/// `A x = b` by Gaussian elimination with partial pivoting, for the small fixed-size
/// systems of the inverse Legendre transform (nalgebra's LU needs a type-level dimension
/// that a const generic `D` does not give); `None` for a singular `A`.
fn solve_small<const D: usize>(
    mut a: SMatrix<f64, D, D>,
    mut b: SVector<f64, D>,
) -> Option<SVector<f64, D>> {
    for k in 0..D {
        let pivot = (k..D).max_by(|&i, &j| a[(i, k)].abs().total_cmp(&a[(j, k)].abs()))?;
        if a[(pivot, k)] == 0.0 || !a[(pivot, k)].is_finite() {
            return None;
        }
        a.swap_rows(k, pivot);
        b.swap_rows(k, pivot);
        for i in k + 1..D {
            let factor = a[(i, k)] / a[(k, k)];
            for j in k..D {
                a[(i, j)] -= factor * a[(k, j)];
            }
            b[i] -= factor * b[k];
        }
    }
    for k in (0..D).rev() {
        let tail: f64 = (k + 1..D).map(|j| a[(k, j)] * b[j]).sum();
        b[k] = (b[k] - tail) / a[(k, k)];
    }
    Some(b)
}

/// The state at a step: time, configuration, body momentum and velocity.
///
/// On SO(3) (`State`, the default parameters) the configuration is the attitude
/// ([`State::attitude`]); on SE(3) (`State<SE3, 6>`) it is `(R, x)`, and
/// [`State::position`], [`State::linear_velocity`] give the centre of mass and its
/// space-frame velocity `ẋ = R v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State<E = SO3, const D: usize = 3> {
    /// Time.
    pub time: f64,
    /// `g = world_from_body`.
    pub configuration: E,
    /// Body momentum `μ = ∂ℓ/∂ξ`.
    pub momentum: SVector<f64, D>,
    /// Body velocity `ξ` with `∂ℓ/∂ξ(t, g, ξ) = μ` (on SO(3) the angular velocity `Ω`;
    /// on SE(3) `(Ω, v)` with `v = Rᵀẋ`).
    pub velocity: SVector<f64, D>,
}

impl<E, const D: usize> State<E, D>
where
    E: LieGroup<Scalar = f64, Tangent = SVector<f64, D>, Jacobian = SMatrix<f64, D, D>>,
{
    /// The spatial (world-frame) momentum `Ad_{g⁻¹}ᵀ μ`: on SO(3) `Rμ`, on SE(3)
    /// `(RJΩ + x × mẋ, mẋ)` (angular momentum about the world origin, linear momentum).
    /// Its components along the symmetries of `ℓ` are conserved.
    pub fn spatial_momentum(&self) -> SVector<f64, D> {
        self.configuration.coadjoint_action(&self.momentum)
    }

    /// Energy `⟨μ, ξ⟩ − ℓ(t, g, ξ)`.
    pub fn energy<S>(&self, system: &S) -> f64
    where
        S: System<D>,
        S::Group: ConfigurationGroup<D, Element<f64> = E>,
    {
        self.momentum.dot(&self.velocity)
            - system.lagrangian(self.time, &self.configuration, &self.velocity)
    }
}

impl State<SO3, 3> {
    /// `R = world_from_body`.
    pub fn attitude(&self) -> &SO3 {
        &self.configuration
    }

    /// `|μ|²`, the Casimir: conserved by the free rigid body.
    pub fn casimir(&self) -> f64 {
        self.momentum.norm_squared()
    }
}

impl State<SE3, 6> {
    /// `R = world_from_body`.
    pub fn attitude(&self) -> &SO3 {
        self.configuration.rotation()
    }

    /// The centre of mass `x`, world frame.
    pub fn position(&self) -> Vector3<f64> {
        *self.configuration.translation()
    }

    /// The body angular velocity `Ω`.
    pub fn angular_velocity(&self) -> Vector3<f64> {
        self.velocity.fixed_rows::<3>(0).into_owned()
    }

    /// The centre of mass velocity `ẋ = R v`, world frame.
    pub fn linear_velocity(&self) -> Vector3<f64> {
        self.configuration.rotation().matrix() * self.velocity.fixed_rows::<3>(3)
    }
}

/// `(L_ξη, L_ξξ)` of `L(η, ξ) = ℓ(t, g exp(η), ξ)` at `η = 0`: how the body momentum
/// moves with the configuration (body frame) and the velocity. From the system's closed
/// form where it has one ([`System::momentum_derivatives`], or
/// [`System::local_derivatives`], whose mixed block is zero by contract); a
/// left-invariant `ℓ` has no mixed block; otherwise one hyper-dual number through `ℓ`
/// (with `exp` to second order: only first order in `η` is read).
pub(crate) fn legendre_blocks<S: System<D>, const D: usize>(
    system: &S,
    time: f64,
    configuration: &<S::Group as ConfigurationGroup<D>>::Element<f64>,
    velocity: &SVector<f64, D>,
) -> (SMatrix<f64, D, D>, SMatrix<f64, D, D>) {
    if let Some(blocks) = system.momentum_derivatives(time, configuration, velocity) {
        return blocks;
    }
    if let Some(local) = system.local_derivatives(time, configuration, velocity, true) {
        return (SMatrix::zeros(), local.velocity_hessian);
    }
    let (_, _, hessian) = num_dual::hessian(
        |xi: SVector<Dual2SVec64<D>, D>| {
            let g = <S::Group as ConfigurationGroup<D>>::lift(configuration);
            system.lagrangian(time, &g, &xi)
        },
        velocity,
    );
    if system.is_left_invariant() {
        return (SMatrix::zeros(), hessian);
    }
    let zero = SVector::<f64, D>::zeros();
    let (_, _, _, mixed) = num_dual::partial_hessian(
        |(xi, eta): (
            SVector<HyperDualSVec64<D, D>, D>,
            SVector<HyperDualSVec64<D, D>, D>,
        )| {
            let g = <S::Group as ConfigurationGroup<D>>::lift(configuration)
                .compose(&<S::Group as ConfigurationGroup<D>>::exp_second_order(&eta));
            system.lagrangian(time, &g, &xi)
        },
        (velocity, &zero),
    );
    (mixed, hessian)
}
