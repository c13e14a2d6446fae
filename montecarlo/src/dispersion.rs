//! Dispersions: how each member of a Monte Carlo run departs from the nominal body.
//!
//! A [`Dispersions`] spec names, for each dispersed quantity, the [`Dispersion`] of its
//! perturbation (normal, truncated normal, uniform). A [`Plan`] holds the nominal body, the
//! spec and a seed, checks up front that no member can be non-physical, and draws member
//! `i` ([`Plan::member`]) from `(seed, i)` alone: every quantity has its own counter-based
//! stream (ChaCha12 keyed by the seed and the quantity, its stream number the member), so
//! a member is the same whatever the thread count, the order the members are drawn in,
//! the machine, and whichever other quantities are dispersed.
//!
//! What each perturbation means (`d` a draw of the quantity's dispersion):
//!
//! | key | quantity | member |
//! |---|---|---|
//! | `attitude` | each component of a rotation vector `δθ`, rad | `R₀ = R̄₀ exp(δθ̂)` (body frame) |
//! | `omega` | each component, rad/s | `Ω₀ = Ω̄₀ + d` |
//! | `inertia` | each principal moment, relative | `J_i = J̄_i (1 + d_i)` |
//! | `inertia_misalignment` | each component of a rotation vector `δφ` of the principal axes, rad | `J = P exp(δφ̂) diag(J_i) exp(δφ̂)ᵀ Pᵀ` |
//! | `mass` | relative | `m = m̄ (1 + d)` |
//! | `torque` | each component of a constant body torque, N·m | `τ = τ̄ + d` |
//! | `wheel_inertia` | each wheel's axial inertia, relative | `I_k = Ī_k (1 + d_k)` |
//! | `wheel_axis` | each component of a rotation vector of each wheel's axis, rad | `a_k = exp(δ̂_k) ā_k` |
//!
//! A relative perturbation must keep its quantity positive, and the principal moments must
//! keep the triangle inequality: a [`Dispersion::Normal`] on a relative quantity can break
//! either, so it is refused; a bounded one is refused when its bound could.

use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::{Inertia, MechanicsError};
use nalgebra::{Matrix3, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha12Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};

/// The distribution of one perturbation (in the units of its quantity: rad, rad/s, N·m,
/// or a fraction for the relative ones).
///
/// In a TOML spec: `omega = { distribution = "normal", sigma = 0.01 }`,
/// `inertia = { distribution = "truncated_normal", sigma = 0.05, bound = 0.15 }`,
/// `attitude = { distribution = "uniform", half_width = 0.02 }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "distribution", rename_all = "snake_case", deny_unknown_fields)]
pub enum Dispersion {
    /// Normal, mean 0, standard deviation `sigma`.
    Normal {
        /// The standard deviation, `≥ 0`.
        sigma: f64,
    },
    /// Normal, mean 0, standard deviation `sigma`, conditioned on `|x| ≤ bound` (drawn by
    /// rejection; `bound ≥ sigma/10`, which accepts at least 8% of the draws).
    TruncatedNormal {
        /// The standard deviation of the normal it truncates, `> 0`.
        sigma: f64,
        /// The largest `|x|`, `≥ sigma/10`.
        bound: f64,
    },
    /// Uniform on `[−half_width, half_width]`.
    Uniform {
        /// Half the width, `≥ 0`.
        half_width: f64,
    },
}

impl Dispersion {
    /// The largest `|x|` it draws, `None` for the unbounded normal.
    pub fn bound(&self) -> Option<f64> {
        match *self {
            Dispersion::Normal { sigma } => (sigma == 0.0).then_some(0.0),
            Dispersion::TruncatedNormal { bound, .. } => Some(bound),
            Dispersion::Uniform { half_width } => Some(half_width),
        }
    }

    /// One draw.
    pub fn sample(&self, rng: &mut impl rand::Rng) -> f64 {
        match *self {
            Dispersion::Normal { sigma } => {
                let z: f64 = StandardNormal.sample(rng);
                sigma * z
            }
            Dispersion::TruncatedNormal { sigma, bound } => loop {
                let z: f64 = StandardNormal.sample(rng);
                let x = sigma * z;
                if x.abs() <= bound {
                    return x;
                }
            },
            Dispersion::Uniform { half_width } => {
                // The closed interval: u in [0, 1].
                let u: f64 = rng.random();
                half_width * (2.0 * u - 1.0)
            }
        }
    }

    /// Refuses parameters that are not finite or out of range, naming `key`.
    fn check(&self, key: &'static str) -> Result<(), DispersionError> {
        let invalid = |reason: String| DispersionError::Invalid { key, reason };
        match *self {
            Dispersion::Normal { sigma } if !(sigma >= 0.0 && sigma.is_finite()) => Err(invalid(
                format!("sigma = {sigma}: a standard deviation is finite and ≥ 0"),
            )),
            Dispersion::TruncatedNormal { sigma, bound } => {
                if !(sigma > 0.0 && sigma.is_finite()) {
                    Err(invalid(format!(
                        "sigma = {sigma}: a truncated normal's standard deviation is finite \
                         and > 0"
                    )))
                } else if !(bound >= 0.1 * sigma && bound.is_finite()) {
                    Err(invalid(format!(
                        "bound = {bound} with sigma = {sigma}: the bound is finite and at \
                         least sigma/10 (narrower, take a uniform dispersion)"
                    )))
                } else {
                    Ok(())
                }
            }
            Dispersion::Uniform { half_width }
                if !(half_width >= 0.0 && half_width.is_finite()) =>
            {
                Err(invalid(format!(
                    "half_width = {half_width}: a half width is finite and ≥ 0"
                )))
            }
            _ => Ok(()),
        }
    }
}

/// Which quantities are dispersed, and how (module documentation); `None` keeps a
/// quantity nominal. Read from TOML with `serde` (unknown keys refused).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dispersions {
    /// Each component of a body-frame rotation vector of the start attitude, rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attitude: Option<Dispersion>,
    /// Added to each component of the start rates, rad/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub omega: Option<Dispersion>,
    /// Each principal moment, relative.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<Dispersion>,
    /// Each component of a rotation vector of the principal axes, rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia_misalignment: Option<Dispersion>,
    /// The mass, relative.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<Dispersion>,
    /// Added to each component of a constant body torque, N·m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque: Option<Dispersion>,
    /// Each wheel's axial inertia, relative.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wheel_inertia: Option<Dispersion>,
    /// Each component of a rotation vector of each wheel's axis, rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wheel_axis: Option<Dispersion>,
}

/// A body and its start: the nominal every member departs from, or a member's draw.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// The inertia (diagonal or full).
    pub inertia: Inertia,
    /// `R₀`, world from body.
    pub attitude: SO3,
    /// `Ω₀`, body frame.
    pub omega: Vector3<f64>,
    /// The mass, for a body in space or a heavy top (`None` for a body whose motion does
    /// not depend on it).
    pub mass: Option<f64>,
    /// A constant body torque.
    pub torque: Vector3<f64>,
    /// The wheels' axial inertias (empty without wheels).
    pub wheel_inertias: Vec<f64>,
    /// The wheels' unit axes, body frame (as many as `wheel_inertias`).
    pub wheel_axes: Vec<Vector3<f64>>,
}

impl Body {
    /// A body of `inertia` from `(attitude, omega)`: no mass, torque or wheels.
    pub fn new(inertia: Inertia, attitude: SO3, omega: Vector3<f64>) -> Self {
        Self {
            inertia,
            attitude,
            omega,
            mass: None,
            torque: Vector3::zeros(),
            wheel_inertias: Vec::new(),
            wheel_axes: Vec::new(),
        }
    }
}

/// One member: its index, the plan's seed, and the body drawn for it (its inertia is
/// diagonal unless the principal axes are dispersed or the nominal's is full).
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    /// The member's index `i`.
    pub index: u64,
    /// The plan's seed: `(seed, index)` reproduce the member.
    pub seed: u64,
    /// What was drawn.
    pub body: Body,
}

/// Why a plan was refused, or a member could not be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DispersionError {
    /// A dispersion's parameters out of range.
    #[error("dispersion {key}: {reason}")]
    Invalid {
        /// The dispersed quantity's key.
        key: &'static str,
        /// What is wrong and what to give.
        reason: String,
    },
    /// A dispersion that can make some member non-physical.
    #[error("dispersion {key}: {reason}")]
    NotPhysical {
        /// The dispersed quantity's key.
        key: &'static str,
        /// Which member quantity it could break, and the bound that keeps it.
        reason: String,
    },
    /// A dispersion of a quantity the nominal body does not have.
    #[error("dispersion {key}: the nominal body has no {what} to disperse")]
    NotApplicable {
        /// The dispersed quantity's key.
        key: &'static str,
        /// What is missing.
        what: &'static str,
    },
    /// The nominal body refused as it stands.
    #[error("nominal body: {0}")]
    Nominal(String),
    /// A member whose drawn body the mechanics refused (a gyrostat whose drawn wheels
    /// leave no positive-definite body inertia, for instance).
    #[error("member {index} (seed {seed}): {source}")]
    Member {
        /// The member.
        index: u64,
        /// The plan's seed.
        seed: u64,
        /// The mechanics' refusal.
        source: MechanicsError,
    },
}

/// The streams of the quantities: fixed numbers, so that adding a dispersion of one
/// quantity leaves every other quantity's draws as they were.
#[derive(Clone, Copy)]
enum Quantity {
    Attitude = 1,
    Omega = 2,
    Inertia = 3,
    Misalignment = 4,
    Mass = 5,
    Torque = 6,
    WheelInertia = 7,
    WheelAxis = 8,
}

/// The generator of `quantity` for member `index` of `seed`: ChaCha12 keyed by the seed
/// and the quantity, its stream the member.
fn stream(seed: u64, quantity: Quantity, index: u64) -> ChaCha12Rng {
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    key[8..16].copy_from_slice(&(quantity as u64).to_le_bytes());
    let mut rng = ChaCha12Rng::from_seed(key);
    rng.set_stream(index);
    rng
}

/// The nominal body, the dispersions and the seed: member `i` is [`Plan::member`]`(i)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    nominal: Body,
    dispersions: Dispersions,
    seed: u64,
}

impl Plan {
    /// A plan, checked: every dispersion's parameters in range, a dispersed quantity the
    /// nominal has, and no member that could be non-physical (a relative perturbation
    /// that could reach −1, or principal moments that could break the triangle
    /// inequality).
    ///
    /// # Errors
    /// [`DispersionError::Invalid`], [`DispersionError::NotPhysical`],
    /// [`DispersionError::NotApplicable`], naming the dispersion's key;
    /// [`DispersionError::Nominal`] for wheel axes and inertias of different counts or a
    /// mass that is not positive.
    pub fn new(
        nominal: Body,
        dispersions: Dispersions,
        seed: u64,
    ) -> Result<Self, DispersionError> {
        if nominal.wheel_axes.len() != nominal.wheel_inertias.len() {
            return Err(DispersionError::Nominal(format!(
                "{} wheel axes for {} wheel inertias: one axis per wheel",
                nominal.wheel_axes.len(),
                nominal.wheel_inertias.len()
            )));
        }
        if let Some(m) = nominal.mass.filter(|m| !(*m > 0.0 && m.is_finite())) {
            return Err(DispersionError::Nominal(format!(
                "mass {m}: a mass is positive and finite"
            )));
        }
        let d = &dispersions;
        let all = [
            ("attitude", d.attitude),
            ("omega", d.omega),
            ("inertia", d.inertia),
            ("inertia_misalignment", d.inertia_misalignment),
            ("mass", d.mass),
            ("torque", d.torque),
            ("wheel_inertia", d.wheel_inertia),
            ("wheel_axis", d.wheel_axis),
        ];
        for (key, dispersion) in all {
            if let Some(dispersion) = dispersion {
                dispersion.check(key)?;
            }
        }
        let wheels = !nominal.wheel_inertias.is_empty();
        for (key, dispersed, present, what) in [
            ("mass", d.mass.is_some(), nominal.mass.is_some(), "mass"),
            ("wheel_inertia", d.wheel_inertia.is_some(), wheels, "wheels"),
            ("wheel_axis", d.wheel_axis.is_some(), wheels, "wheels"),
        ] {
            if dispersed && !present {
                return Err(DispersionError::NotApplicable { key, what });
            }
        }
        for (key, dispersion) in [("mass", d.mass), ("wheel_inertia", d.wheel_inertia)] {
            if let Some(dispersion) = dispersion {
                relative_bound(key, &dispersion, 1.0, "its positivity")?;
            }
        }
        if let Some(dispersion) = d.inertia {
            // J_a(1 + β) ≤ (J_b + J_c)(1 − β) for every a at the worst draw β: β at most
            // min_a (J_b + J_c − J_a)/tr J.
            let j = nominal.inertia.principal_moments();
            let trace = j[0] + j[1] + j[2];
            let room = (0..3)
                .map(|a| (trace - 2.0 * j[a]) / trace)
                .fold(f64::INFINITY, f64::min);
            relative_bound(
                "inertia",
                &dispersion,
                room,
                "the principal moments' triangle inequality (J_a ≤ J_b + J_c)",
            )?;
        }
        Ok(Self {
            nominal,
            dispersions,
            seed,
        })
    }

    /// The nominal body.
    pub fn nominal(&self) -> &Body {
        &self.nominal
    }

    /// The dispersions.
    pub fn dispersions(&self) -> &Dispersions {
        &self.dispersions
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Member `index`, from `(seed, index)` alone.
    ///
    /// # Errors
    /// [`DispersionError::Member`] where the mechanics refuses the drawn inertia (the plan's
    /// checks leave none for a body without wheels; rounding at a bound's very edge
    /// aside).
    pub fn member(&self, index: u64) -> Result<Member, DispersionError> {
        let (seed, d, n) = (self.seed, &self.dispersions, &self.nominal);
        let vector = |dispersion: Option<Dispersion>, quantity| {
            dispersion.map(|dispersion| {
                let mut rng = stream(seed, quantity, index);
                Vector3::from_fn(|_, _| dispersion.sample(&mut rng))
            })
        };
        let attitude = match vector(d.attitude, Quantity::Attitude) {
            Some(delta) => n.attitude.compose(&SO3::exp(&delta)),
            None => n.attitude,
        };
        let omega = n.omega + vector(d.omega, Quantity::Omega).unwrap_or_default();
        let torque = n.torque + vector(d.torque, Quantity::Torque).unwrap_or_default();
        let member_error = |source| DispersionError::Member {
            index,
            seed,
            source,
        };
        let moments = n.inertia.principal_moments();
        let moments = match vector(d.inertia, Quantity::Inertia) {
            Some(delta) => [0, 1, 2].map(|k| moments[k] * (1.0 + delta[k])),
            None => moments,
        };
        let misalignment = vector(d.inertia_misalignment, Quantity::Misalignment);
        let inertia = if n.inertia.is_diagonal() && misalignment.is_none() {
            Inertia::from_principal_moments(moments)
        } else {
            let rotation =
                misalignment.map_or(Matrix3::identity(), |delta| *SO3::exp(&delta).matrix());
            let axes = n.inertia.principal_axes() * rotation;
            let tensor = axes * Matrix3::from_diagonal(&Vector3::from(moments)) * axes.transpose();
            Inertia::from_tensor((tensor + tensor.transpose()) * 0.5)
        }
        .map_err(member_error)?;
        let mass = n.mass.map(|m| match d.mass {
            Some(dispersion) => {
                m * (1.0 + dispersion.sample(&mut stream(seed, Quantity::Mass, index)))
            }
            None => m,
        });
        let mut wheel_inertias = n.wheel_inertias.clone();
        if let Some(dispersion) = d.wheel_inertia {
            let mut rng = stream(seed, Quantity::WheelInertia, index);
            for inertia in &mut wheel_inertias {
                *inertia *= 1.0 + dispersion.sample(&mut rng);
            }
        }
        let mut wheel_axes = n.wheel_axes.clone();
        if let Some(dispersion) = d.wheel_axis {
            let mut rng = stream(seed, Quantity::WheelAxis, index);
            for axis in &mut wheel_axes {
                let delta = Vector3::from_fn(|_, _| dispersion.sample(&mut rng));
                *axis = (SO3::exp(&delta).matrix() * *axis).normalize();
            }
        }
        Ok(Member {
            index,
            seed,
            body: Body {
                inertia,
                attitude,
                omega,
                mass,
                torque,
                wheel_inertias,
                wheel_axes,
            },
        })
    }
}

/// Refuses a relative dispersion of `key` that can reach `room` (a perturbation of −1
/// makes the quantity zero): unbounded, or bounded at or past it.
fn relative_bound(
    key: &'static str,
    dispersion: &Dispersion,
    room: f64,
    what: &str,
) -> Result<(), DispersionError> {
    match dispersion.bound() {
        Some(bound) if bound < room => Ok(()),
        Some(bound) => Err(DispersionError::NotPhysical {
            key,
            reason: format!(
                "relative draws up to {bound:.6} could break {what}; keep the bound below \
                 {room:.6}"
            ),
        }),
        None => Err(DispersionError::NotPhysical {
            key,
            reason: format!(
                "a normal relative perturbation is unbounded and could break {what}; take a \
                 truncated_normal (or uniform) with a bound below {room:.6}"
            ),
        }),
    }
}
