//! Derivatives of the charts' maps in closed form, and the dual-number routes beside them.
//!
//! [`MatrixJet`] is `M(x) = e(s) I + a(s) x̂ + b(s) x̂²` (`s = |x|²`) with its first and
//! second derivatives in `x`, from the coefficients' derivatives in `s`: every map of the
//! SO(3) charts ([`So3Chart`](crate::So3Chart)'s `A`, `Φ`) has this Rodrigues form, so the
//! closed-form [`ChartDerivatives`](crate::ChartDerivatives) of SO(3), of SE(3)'s
//! rotation–translation chart and of any product with SO(3) are built from it.
//!
//! With `s = |x|²` (so `∂_k s = 2x_k`) and `D_k = ∂_k(x̂²) = e_k xᵀ + x e_kᵀ − 2x_k I`
//! (from `x̂² = x xᵀ − |x|² I`), the derivatives are
//! `∂_k M = 2x_k (e′I + a′x̂ + b′x̂²) + a ê_k + b D_k` and
//! `∂_k∂_l M = 4x_k x_l (e″I + a″x̂ + b″x̂²) + 2δ_kl (e′I + a′x̂ + b′x̂²)
//! + 2x_k (a′ê_l + b′D_l) + 2x_l (a′ê_k + b′D_k) + b (e_k e_lᵀ + e_l e_kᵀ − 2δ_kl I)`.
//!
//! [`seeded`] and [`jacobian_of`] are the first-order dual-number route (one direction per
//! coordinate), the reference the closed forms are tested against.
//!
//! ```
//! use lgsvi_lie::jet::MatrixJet;
//! use lgsvi_lie::{ExpChart, So3Chart};
//! use nalgebra::Vector3;
//! use num_dual::Dual2_64;
//!
//! // The jet of exp's left differential A(x) at x, from its Rodrigues coefficients at s = |x|².
//! let x = Vector3::new(0.3, -0.2, 0.5);
//! let s = Dual2_64::new(x.norm_squared(), 1.0, 0.0);
//! let coefficients = ExpChart.rotation_left_differential_coefficients(s).unwrap();
//! let a = MatrixJet::from_rodrigues(&coefficients, &x);
//! assert!((a.value - ExpChart.rotation_left_differential(&x)).amax() < 1e-15);
//! // Column k of first_times(v) is ∂_k A(x) v: against a central difference.
//! let v = Vector3::new(1.0, 2.0, -1.0);
//! let e = 1e-6;
//! let dx = Vector3::new(e, 0.0, 0.0);
//! let difference = (ExpChart.rotation_left_differential(&(x + dx))
//!     - ExpChart.rotation_left_differential(&(x - dx)))
//!     * v
//!     / (2.0 * e);
//! assert!((a.first_times(&v).column(0) - difference).amax() < 1e-9);
//! ```

use crate::chart::RodriguesCoefficients;
use crate::so3::{hat, vee};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use num_dual::{Dual2_64, Dual64, DualSVec64};

/// A 3×3 matrix function `M(x) = e(s) I + a(s) x̂ + b(s) x̂²` of `x ∈ ℝ³` with the
/// derivatives of its coefficients in `s`: its first partial derivatives `∂_k M`
/// contracted with a vector ([`MatrixJet::first_times`],
/// [`MatrixJet::first_transposed_times`]); second
/// derivatives are only ever needed contracted with a matrix, `⟨G, ∂_k∂_l M⟩`, which
/// [`MatrixJet::second_contracted`] forms directly.
#[derive(Debug, Clone, Copy)]
pub struct MatrixJet {
    /// `M(x)`.
    pub value: Matrix3<f64>,
    x: Vector3<f64>,
    /// `(e, a, b)`, their first and their second derivatives in `s`.
    c0: [f64; 3],
    c1: [f64; 3],
    c2: [f64; 3],
}

/// `γ` with `⟨G, ŷ⟩ = γ·y` for every `y`: the axial vector of `G − Gᵀ`.
#[inline]
pub fn axial(g: &Matrix3<f64>) -> Vector3<f64> {
    vee(&(g - g.transpose()))
}

/// `ê_k`.
#[inline]
pub fn unit_hat(k: usize) -> Matrix3<f64> {
    let mut e = Vector3::zeros();
    e[k] = 1.0;
    hat(&e)
}

impl MatrixJet {
    /// The jet at `x` from the coefficients evaluated at the dual number `s + ε` (value,
    /// first and second derivative in `s`).
    #[inline]
    pub fn from_rodrigues(c: &RodriguesCoefficients<Dual2_64>, x: &Vector3<f64>) -> Self {
        let re = RodriguesCoefficients {
            identity: c.identity.re,
            hat: c.hat.re,
            hat_squared: c.hat_squared.re,
        };
        Self {
            value: re.matrix(x),
            x: *x,
            c0: [re.identity, re.hat, re.hat_squared],
            c1: [c.identity.v1, c.hat.v1, c.hat_squared.v1],
            c2: [c.identity.v2, c.hat.v2, c.hat_squared.v2],
        }
    }

    /// As [`MatrixJet::from_rodrigues`] from coefficients at a first-order dual number
    /// (the second derivatives set to zero): enough for the value and first derivatives,
    /// which is all a gradient needs, at about two thirds of the cost. Such a jet's
    /// [`MatrixJet::second_contracted`] is not the second derivative: do not ask it for one.
    #[inline]
    pub fn from_rodrigues_first_order(c: &RodriguesCoefficients<Dual64>, x: &Vector3<f64>) -> Self {
        let lift = |d: Dual64| Dual2_64::new(d.re, d.eps, 0.0);
        Self::from_rodrigues(
            &RodriguesCoefficients {
                identity: lift(c.identity),
                hat: lift(c.hat),
                hat_squared: lift(c.hat_squared),
            },
            x,
        )
    }

    /// The matrix with columns `∂_k M v`: `u xᵀ − a v̂ + b (x·v) I + b x vᵀ` with
    /// `u = 2e′v + 2a′ x×v + 2b′ x̂²v − 2b v` (the formula for `∂_k M` applied to `v`,
    /// `D_k v = e_k (x·v) + x v_k − 2x_k v`), without forming the three matrices.
    #[inline]
    pub fn first_times(&self, v: &Vector3<f64>) -> Matrix3<f64> {
        self.first_applied(v, 1.0)
    }

    /// The matrix with rows `((∂_k M)ᵀ g)ᵀ`, i.e. entries `gᵀ ∂_k M e_b`: `(∂_k M)ᵀ` is
    /// `∂_k M` with its skew terms (`a`, `a′`) negated (`x̂²` and `D_k` are symmetric), so
    /// this is [`MatrixJet::first_times`] of `g` with those signs flipped, transposed.
    #[inline]
    pub fn first_transposed_times(&self, g: &Vector3<f64>) -> Matrix3<f64> {
        self.first_applied(g, -1.0).transpose()
    }

    /// Columns `∂_k M' v` for `M' = e I + σ a x̂ + b x̂²` (`σ = ±1`).
    #[inline]
    fn first_applied(&self, v: &Vector3<f64>, skew_sign: f64) -> Matrix3<f64> {
        let x = &self.x;
        let [_, a, b] = self.c0;
        let [e1, a1, b1] = self.c1;
        let (a, a1) = (skew_sign * a, skew_sign * a1);
        let xv = x.dot(v);
        // x̂²v = x (x·v) − |x|² v.
        let xh2v = x * xv - v * x.norm_squared();
        let u = v * (2.0 * e1 - 2.0 * b) + x.cross(v) * (2.0 * a1) + xh2v * (2.0 * b1);
        let mut out = u * x.transpose() - hat(v) * a + x * v.transpose() * b;
        for i in 0..3 {
            out[(i, i)] += b * xv;
        }
        out
    }

    /// `[⟨G, ∂_k∂_l M⟩]_kl`, from the formula in the module's documentation with
    /// `⟨G, I⟩ = tr G`, `⟨G, ŷ⟩ = γ·y` (`γ` the axial vector of `G − Gᵀ`),
    /// `⟨G, x̂²⟩ = xᵀGx − s tr G`, `⟨G, D_k⟩ = ((G + Gᵀ)x − 2 tr G x)_k` and
    /// `⟨G, e_k e_lᵀ + e_l e_kᵀ⟩ = G_kl + G_lk`.
    #[inline]
    pub fn second_contracted(&self, g: &Matrix3<f64>) -> Matrix3<f64> {
        let x = &self.x;
        let [_, _, b] = self.c0;
        let [e1, a1, b1] = self.c1;
        let [e2, a2, b2] = self.c2;
        let t = g.trace();
        let gamma = axial(g);
        let sym = g + g.transpose();
        let gx = gamma.dot(x);
        let q = x.dot(&(g * x)) - x.norm_squared() * t;
        let u = sym * x - x * (2.0 * t);
        let outer = 4.0 * (e2 * t + a2 * gx + b2 * q);
        let diagonal = 2.0 * (e1 * t + a1 * gx + b1 * q) - 2.0 * b * t;
        let w = gamma * (2.0 * a1) + u * (2.0 * b1);
        let mut out = x * x.transpose() * outer + x * w.transpose() + w * x.transpose() + sym * b;
        for i in 0..3 {
            out[(i, i)] += diagonal;
        }
        out
    }
}

/// `x` as `D` first-order dual numbers, one direction each.
pub fn seeded<const D: usize>(x: &SVector<f64, D>) -> SVector<DualSVec64<D>, D> {
    SVector::from_fn(|i, _| {
        DualSVec64::<D>::new(
            x[i],
            num_dual::Derivative::some(SVector::from_fn(|j, _| if i == j { 1.0 } else { 0.0 })),
        )
    })
}

/// The `D × D` matrix `∂y_r/∂x_a` of first-order dual numbers `y` seeded by [`seeded`].
pub fn jacobian_of<const D: usize>(y: &SVector<DualSVec64<D>, D>) -> SMatrix<f64, D, D> {
    SMatrix::from_fn(|r, a| {
        y[r].eps
            .unwrap_generic(nalgebra::Const::<D>, nalgebra::Const::<1>)[a]
    })
}
