//! Charts `Φ: 𝔤 → G` with `Φ(0) = e`, their trivialised differentials, and natural charts.
//!
//! A chart's **left-trivialised differential** `A(ξ)` is defined by
//! `Φ(ξ)⁻¹ DΦ(ξ)[v] = (A(ξ) v)^`, its **right-trivialised** one `B(ξ)` by
//! `DΦ(ξ)[v] Φ(ξ)⁻¹ = (B(ξ) v)^`. For the exponential map these are the right and left
//! Jacobians `J_r` and `J_l`. The **natural chart** at `g` is `ξ ↦ g Φ(ξ)`, with inverse
//! `h ↦ Φ⁻¹(g⁻¹ h)`; it is equivariant: `φ_{kg}(k h) = φ_g(h)`.
//!
//! | chart | `Φ` on SO(3) | rotation angle of `Φ(ξ)` | `Φ⁻¹` defined for | differential invertible for |
//! |---|---|---|---|---|
//! | [`ExpChart`] | `exp(ξ̂)` | `|ξ|` | angle `< π` | `|ξ| < 2π` |
//! | [`CayleyChart`] | `(I − ξ̂/2)⁻¹(I + ξ̂/2)` | `2 atan(|ξ|/2)` | angle `< π` | every `ξ` |
//! | [`UnscaledCayleyChart`] (the paper's) | `(I − q̂)(I + q̂)⁻¹` | `−2 atan|q|` (about `q`) | angle `< π` | every `q` |
//!
//! On SE(3) each chart acts on the rotation as above and on the translation through a
//! linear map `M(ω)`: `Φ(ω, v) = (Φ(ω), M(ω) v)` — `J_l(ω)` for exp (the usual SE(3)
//! exponential), `(I − ω̂/2)⁻¹` for Cayley (the 4×4 Cayley transform), `−2(I + q̂)⁻¹` for
//! the unscaled Cayley (likewise). The differentials follow in closed form from the SO(3)
//! ones, `M` and `N(ω, v) = ∂(M(ω)v)/∂ω`:
//! `A = [[A_ω, 0], [RᵀN, RᵀM]]`, `B = [[B_ω, 0], [N + x̂B_ω, M]]`, with `x = M v`.

mod cayley;
mod exp;
mod lift;

pub use cayley::{CayleyChart, UnscaledCayleyChart};
pub use exp::ExpChart;

use crate::error::LieError;
use crate::group::LieGroup;
use nalgebra::{Matrix3, RealField, Vector3};
use std::fmt::Debug;
use std::str::FromStr;

/// A chart `Φ: 𝔤 → G` around the identity and its trivialised differentials.
///
/// Implemented for [`SO3`](crate::SO3) and [`SE3`](crate::SE3) by every [`So3Chart`]
/// ([`ExpChart`], [`CayleyChart`], [`UnscaledCayleyChart`], and the run-time choice
/// [`ChartKind`]). All methods are generic over the scalar, so dual numbers pass through
/// `to_group` and the differentials: exact derivatives of any order come that way
/// ([`dual_number_derivatives`](crate::dual_number_derivatives) takes a chart's second
/// derivatives so).
///
/// ```
/// use lgsvi_lie::{Chart, ExpChart, LieGroup, SO3};
/// use nalgebra::Vector3;
/// let xi = Vector3::new(0.1, -0.2, 0.3);
/// let r: SO3 = ExpChart.to_group(&xi);
/// assert!((ExpChart.to_algebra(&r)? - xi).norm() < 1e-15);
/// // A(ξ) A(ξ)⁻¹ = I
/// let a = <ExpChart as Chart<SO3>>::left_differential(&ExpChart, &xi);
/// let a_inv = <ExpChart as Chart<SO3>>::left_differential_inverse(&ExpChart, &xi)?;
/// assert!((a * a_inv - nalgebra::Matrix3::identity()).norm() < 1e-15);
/// # Ok::<(), lgsvi_lie::LieError>(())
/// ```
pub trait Chart<G: LieGroup> {
    /// Name, for messages ("exp", "cayley", "cayley-unscaled").
    fn name(&self) -> &'static str;

    /// `Φ(ξ)`. Defined for every `ξ`; see [`Chart::check_domain`] for where it is a
    /// local diffeomorphism.
    fn to_group(&self, xi: &G::Tangent) -> G;

    /// `Φ⁻¹(g)`.
    ///
    /// # Errors
    /// [`LieError::OutsideChart`] when `g` is outside the chart's image (rotation angle
    /// `π` for every chart here).
    fn to_algebra(&self, g: &G) -> Result<G::Tangent, LieError>;

    /// Whether `ξ` is finite and inside the region where `Φ` is a local diffeomorphism
    /// (`|ω| < 2π` for exp; everywhere for the Cayley charts).
    ///
    /// # Errors
    /// [`LieError::NonFinite`] or [`LieError::OutsideChart`].
    fn check_domain(&self, xi: &G::Tangent) -> Result<(), LieError>;

    /// The left-trivialised differential `A(ξ)`: `Φ(ξ)⁻¹ DΦ(ξ)[v] = (A(ξ) v)^`.
    fn left_differential(&self, xi: &G::Tangent) -> G::Jacobian;

    /// `A(ξ)⁻¹`, in closed form.
    ///
    /// # Errors
    /// As [`Chart::check_domain`].
    fn left_differential_inverse(&self, xi: &G::Tangent) -> Result<G::Jacobian, LieError>;

    /// The right-trivialised differential `B(ξ)`: `DΦ(ξ)[v] Φ(ξ)⁻¹ = (B(ξ) v)^`.
    fn right_differential(&self, xi: &G::Tangent) -> G::Jacobian;

    /// `B(ξ)⁻¹`, in closed form.
    ///
    /// # Errors
    /// As [`Chart::check_domain`].
    fn right_differential_inverse(&self, xi: &G::Tangent) -> Result<G::Jacobian, LieError>;
}

/// The SO(3) building blocks of a chart, from which [`Chart`] is implemented for both
/// [`SO3`](crate::SO3) and [`SE3`](crate::SE3). Implement it to bring a chart of your own
/// (say, a higher-order Cayley map); the crate's law tests show what it must satisfy.
///
/// The `*_inverse` differentials here do not check the domain: [`Chart`] calls
/// [`So3Chart::check_rotation_domain`] first.
pub trait So3Chart: Copy + Debug {
    /// Name, for messages.
    fn chart_name(&self) -> &'static str;
    /// The rotation matrix `Φ(ω)`.
    fn rotation_matrix<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T>;
    /// `Φ⁻¹(R)`.
    ///
    /// # Errors
    /// [`LieError::OutsideChart`] outside the chart's image.
    fn rotation_vector<T: RealField + Copy>(&self, r: &Matrix3<T>) -> Result<Vector3<T>, LieError>;
    /// `Φ⁻¹(R)` on the branch nearest `near`, for charts whose domain covers some rotations
    /// more than once: [`ExpChart`]'s domain `|ω| < 2π` holds both `θa` and `(θ − 2π)a`
    /// for a rotation by `θ` about `a`, and [`So3Chart::rotation_vector`] returns the
    /// first (`θ ≤ π`). Following a curve whose rotation grows past `π` (a long step),
    /// pass the previous point as `near` to stay on its branch. The default, for charts
    /// that cover each rotation once, is [`So3Chart::rotation_vector`].
    ///
    /// ```
    /// use lgsvi_lie::{ExpChart, So3Chart};
    /// use nalgebra::Vector3;
    /// // A rotation by 4 rad about z: the principal logarithm is −(2π − 4) ẑ.
    /// let w = Vector3::new(0.0, 0.0, 4.0);
    /// let r = ExpChart.rotation_matrix(&w);
    /// assert!((ExpChart.rotation_vector(&r)?.z + (std::f64::consts::TAU - 4.0)).abs() < 1e-12);
    /// assert!((ExpChart.rotation_vector_near(&r, &Vector3::new(0.0, 0.0, 3.5))? - w).norm() < 1e-12);
    /// # Ok::<(), lgsvi_lie::LieError>(())
    /// ```
    ///
    /// # Errors
    /// As [`So3Chart::rotation_vector`].
    fn rotation_vector_near<T: RealField + Copy>(
        &self,
        r: &Matrix3<T>,
        near: &Vector3<T>,
    ) -> Result<Vector3<T>, LieError> {
        let _ = near;
        self.rotation_vector(r)
    }
    /// The largest rotation angle a curve starting at the identity can reach in this
    /// chart, following its rotation continuously: `π` (the default) for a chart that
    /// covers each rotation once, as the Cayley maps do. A motion that turns further
    /// within one step cannot be represented: the chart would show it as a different,
    /// aliased rotation.
    ///
    /// ```
    /// use lgsvi_lie::{CayleyChart, ExpChart, So3Chart};
    /// assert_eq!(CayleyChart.max_rotation_angle(), std::f64::consts::PI);
    /// assert_eq!(ExpChart.max_rotation_angle(), std::f64::consts::TAU);
    /// ```
    fn max_rotation_angle(&self) -> f64 {
        std::f64::consts::PI
    }
    /// Finite and inside the region where `Φ` is a local diffeomorphism.
    ///
    /// # Errors
    /// [`LieError::NonFinite`] or [`LieError::OutsideChart`].
    fn check_rotation_domain<T: RealField + Copy>(&self, w: &Vector3<T>) -> Result<(), LieError>;
    /// `A(ω)`.
    fn rotation_left_differential<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T>;
    /// `A(ω)⁻¹` (domain not checked).
    fn rotation_left_differential_inverse<T: RealField + Copy>(&self, w: &Vector3<T>)
        -> Matrix3<T>;
    /// `B(ω)`.
    fn rotation_right_differential<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T>;
    /// `B(ω)⁻¹` (domain not checked).
    fn rotation_right_differential_inverse<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
    ) -> Matrix3<T>;
    /// SE(3): the translation map `M(ω)`, `Φ(ω, v) = (Φ(ω), M(ω) v)`.
    fn translation_map<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T>;
    /// SE(3): `M(ω)⁻¹` (domain not checked).
    fn translation_map_inverse<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T>;
    /// SE(3): `N(ω, v) = ∂(M(ω) v)/∂ω`.
    fn translation_map_derivative<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
        v: &Vector3<T>,
    ) -> Matrix3<T>;
    /// `Φ(ω)` in Rodrigues form `e(s) I + a(s) ω̂ + b(s) ω̂²`, `s = |ω|²`, if the chart
    /// has one (`None`, the default, if not). Generic in the scalar, so a dual number in
    /// `s` gives the coefficients' derivatives: callers build exact derivatives of `Φ` in
    /// `ω` from them ([`crate::jet::MatrixJet`] does).
    fn rotation_matrix_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        let _ = s;
        None
    }
    /// `A(ω)` in Rodrigues form, as [`So3Chart::rotation_matrix_coefficients`].
    fn rotation_left_differential_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        let _ = s;
        None
    }
    /// `(Φ, A)` in Rodrigues form together, for callers that need both: the exp chart
    /// shares one evaluation of its trigonometric functions (or series) between them.
    /// The default calls [`So3Chart::rotation_matrix_coefficients`] and
    /// [`So3Chart::rotation_left_differential_coefficients`].
    ///
    /// ```
    /// use lgsvi_lie::{ExpChart, So3Chart};
    /// let s = 0.7_f64;
    /// let (phi, a) = ExpChart.rotation_and_left_differential_coefficients(s).unwrap();
    /// let phi_alone = ExpChart.rotation_matrix_coefficients(s).unwrap();
    /// let a_alone = ExpChart.rotation_left_differential_coefficients(s).unwrap();
    /// assert!((phi.hat - phi_alone.hat).abs() < 1e-16 && a == a_alone);
    /// ```
    #[allow(clippy::type_complexity)]
    fn rotation_and_left_differential_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<(RodriguesCoefficients<T>, RodriguesCoefficients<T>)> {
        self.rotation_matrix_coefficients(s)
            .zip(self.rotation_left_differential_coefficients(s))
    }
}

/// The coefficients of a 3×3 map written `e(s) I + a(s) ω̂ + b(s) ω̂²` with `s = |ω|²`:
/// every map of this crate's charts has that form (see
/// [`So3Chart::rotation_matrix_coefficients`]).
///
/// ```
/// use lgsvi_lie::{ExpChart, So3Chart};
/// use nalgebra::Vector3;
/// let w = Vector3::new(0.3, -0.2, 0.9);
/// let form = ExpChart.rotation_matrix_coefficients(w.norm_squared()).unwrap();
/// assert!((form.matrix(&w) - ExpChart.rotation_matrix(&w)).norm() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodriguesCoefficients<T> {
    /// `e(s)`, the coefficient of `I`.
    pub identity: T,
    /// `a(s)`, the coefficient of `ω̂`.
    pub hat: T,
    /// `b(s)`, the coefficient of `ω̂²`.
    pub hat_squared: T,
}

impl<T: RealField + Copy> RodriguesCoefficients<T> {
    /// `e I + a ω̂ + b ω̂²` at `ω` (with `s = |ω|²` the caller's; the diagonal is formed
    /// as `e − b(ω_j² + ω_k²)`, without cancellation).
    pub fn matrix(&self, w: &Vector3<T>) -> Matrix3<T> {
        let mut m = crate::so3::rodrigues_form(w, self.hat, self.hat_squared);
        let shift = self.identity - T::one();
        for i in 0..3 {
            m[(i, i)] += shift;
        }
        m
    }

    /// `(e I + a ω̂ + b ω̂²)ᵀ y = e y − a ω × y + b ω × (ω × y)`: the transposed matrix
    /// applied to a vector without forming it (for a rotation chart, `Φ(ω)ᵀy`, a world
    /// vector in the body frame).
    ///
    /// ```
    /// use lgsvi_lie::{ExpChart, So3Chart};
    /// use nalgebra::Vector3;
    /// let (w, y) = (Vector3::new(0.3, -0.2, 0.9), Vector3::new(1.0, 2.0, -0.5));
    /// let form = ExpChart.rotation_matrix_coefficients(w.norm_squared()).unwrap();
    /// let direct = ExpChart.rotation_matrix(&w).transpose() * y;
    /// assert!((form.transpose_times(&w, &y) - direct).norm() < 1e-15);
    /// ```
    pub fn transpose_times(&self, w: &Vector3<T>, y: &Vector3<T>) -> Vector3<T> {
        let wy = w.cross(y);
        y * self.identity - wy * self.hat + w.cross(&wy) * self.hat_squared
    }

    /// `(e I + a ω̂ + b ω̂²) y = e y + a ω × y + b ω × (ω × y)`, without forming the matrix.
    ///
    /// ```
    /// use lgsvi_lie::{CayleyChart, So3Chart};
    /// use nalgebra::Vector3;
    /// let (w, y) = (Vector3::new(0.3, -0.2, 0.9), Vector3::new(1.0, 2.0, -0.5));
    /// let form = CayleyChart.rotation_matrix_coefficients(w.norm_squared()).unwrap();
    /// let direct = CayleyChart.rotation_matrix(&w) * y;
    /// assert!((form.times(&w, &y) - direct).norm() < 1e-15);
    /// ```
    pub fn times(&self, w: &Vector3<T>, y: &Vector3<T>) -> Vector3<T> {
        let wy = w.cross(y);
        y * self.identity + wy * self.hat + w.cross(&wy) * self.hat_squared
    }
}

/// The natural chart at a base point `g`: `ξ ↦ g Φ(ξ)`, `h ↦ Φ⁻¹(g⁻¹ h)`.
///
/// ```
/// use lgsvi_lie::{ExpChart, LieGroup, NaturalChart, SO3};
/// use nalgebra::Vector3;
/// let world_from_body = SO3::about_z(1.0);
/// let chart = NaturalChart::new(world_from_body, ExpChart);
/// let xi = Vector3::new(0.0, 0.2, 0.0);
/// let moved = chart.to_group(&xi); // world_from_body · exp(ξ)
/// assert!((chart.to_algebra(&moved)? - xi).norm() < 1e-15);
/// # Ok::<(), lgsvi_lie::LieError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct NaturalChart<G, C> {
    base: G,
    chart: C,
}

impl<G: LieGroup, C: Chart<G>> NaturalChart<G, C> {
    /// The natural chart of `chart` at `base`.
    pub fn new(base: G, chart: C) -> Self {
        Self { base, chart }
    }

    /// The base point `g`.
    pub fn base(&self) -> &G {
        &self.base
    }

    /// The underlying chart `Φ`.
    pub fn chart(&self) -> &C {
        &self.chart
    }

    /// `g Φ(ξ)`.
    pub fn to_group(&self, xi: &G::Tangent) -> G {
        self.base.compose(&self.chart.to_group(xi))
    }

    /// `Φ⁻¹(g⁻¹ h)`.
    ///
    /// # Errors
    /// As [`Chart::to_algebra`].
    pub fn to_algebra(&self, h: &G) -> Result<G::Tangent, LieError> {
        self.chart.to_algebra(&self.base.inverse().compose(h))
    }
}

/// A chart chosen at run time (from a configuration file or a command line).
///
/// ```
/// use lgsvi_lie::ChartKind;
/// let chart: ChartKind = "cayley-unscaled".parse()?;
/// assert_eq!(chart, ChartKind::CayleyUnscaled);
/// assert_eq!(chart.to_string(), "cayley-unscaled");
/// assert!("quaternion".parse::<ChartKind>().is_err());
/// # Ok::<(), lgsvi_lie::ParseChartError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ChartKind {
    /// [`ExpChart`], the default.
    #[default]
    Exp,
    /// [`CayleyChart`].
    Cayley,
    /// [`UnscaledCayleyChart`], the paper's.
    CayleyUnscaled,
}

impl ChartKind {
    /// Every kind, in the order of this enum.
    pub const ALL: [ChartKind; 3] = [ChartKind::Exp, ChartKind::Cayley, ChartKind::CayleyUnscaled];
}

/// An unknown chart name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown chart {0:?}: expected exp, cayley or cayley-unscaled")]
pub struct ParseChartError(pub String);

impl FromStr for ChartKind {
    type Err = ParseChartError;
    fn from_str(s: &str) -> Result<Self, ParseChartError> {
        match s {
            "exp" => Ok(ChartKind::Exp),
            "cayley" => Ok(ChartKind::Cayley),
            "cayley-unscaled" => Ok(ChartKind::CayleyUnscaled),
            other => Err(ParseChartError(other.to_string())),
        }
    }
}

impl std::fmt::Display for ChartKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.chart_name())
    }
}

macro_rules! dispatch {
    ($self:expr, $chart:ident => $body:expr) => {
        match $self {
            ChartKind::Exp => {
                let $chart = ExpChart;
                $body
            }
            ChartKind::Cayley => {
                let $chart = CayleyChart;
                $body
            }
            ChartKind::CayleyUnscaled => {
                let $chart = UnscaledCayleyChart;
                $body
            }
        }
    };
}

impl So3Chart for ChartKind {
    fn chart_name(&self) -> &'static str {
        dispatch!(self, c => c.chart_name())
    }
    fn rotation_matrix<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        dispatch!(self, c => c.rotation_matrix(w))
    }
    fn rotation_vector<T: RealField + Copy>(&self, r: &Matrix3<T>) -> Result<Vector3<T>, LieError> {
        dispatch!(self, c => c.rotation_vector(r))
    }
    fn rotation_vector_near<T: RealField + Copy>(
        &self,
        r: &Matrix3<T>,
        near: &Vector3<T>,
    ) -> Result<Vector3<T>, LieError> {
        dispatch!(self, c => c.rotation_vector_near(r, near))
    }
    fn max_rotation_angle(&self) -> f64 {
        dispatch!(self, c => c.max_rotation_angle())
    }
    fn check_rotation_domain<T: RealField + Copy>(&self, w: &Vector3<T>) -> Result<(), LieError> {
        dispatch!(self, c => c.check_rotation_domain(w))
    }
    fn rotation_left_differential<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        dispatch!(self, c => c.rotation_left_differential(w))
    }
    fn rotation_left_differential_inverse<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
    ) -> Matrix3<T> {
        dispatch!(self, c => c.rotation_left_differential_inverse(w))
    }
    fn rotation_right_differential<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        dispatch!(self, c => c.rotation_right_differential(w))
    }
    fn rotation_right_differential_inverse<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
    ) -> Matrix3<T> {
        dispatch!(self, c => c.rotation_right_differential_inverse(w))
    }
    fn translation_map<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        dispatch!(self, c => c.translation_map(w))
    }
    fn translation_map_inverse<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        dispatch!(self, c => c.translation_map_inverse(w))
    }
    fn translation_map_derivative<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
        v: &Vector3<T>,
    ) -> Matrix3<T> {
        dispatch!(self, c => c.translation_map_derivative(w, v))
    }
    fn rotation_matrix_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        dispatch!(self, c => c.rotation_matrix_coefficients(s))
    }
    fn rotation_left_differential_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        dispatch!(self, c => c.rotation_left_differential_coefficients(s))
    }
    fn rotation_and_left_differential_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<(RodriguesCoefficients<T>, RodriguesCoefficients<T>)> {
        dispatch!(self, c => c.rotation_and_left_differential_coefficients(s))
    }
}
