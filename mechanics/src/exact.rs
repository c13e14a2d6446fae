//! The exact motion of the free rigid body, for validation.
//!
//! A free body with principal moments `J` obeys Euler's equations `μ̇ = μ × Ω`, `Ω = J⁻¹μ`,
//! `Ṙ = RΩ̂`. Their solution is classical (Jacobi 1849; Landau & Lifshitz, *Mechanics*,
//! §37): the body momentum `μ(t)` runs along a *polhode*, the intersection of the sphere
//! `|μ| = M` with the energy ellipsoid `Σ μᵢ²/Jᵢ = 2E`, and is given by the Jacobi
//! elliptic functions `sn, cn, dn`; the attitude follows from `Rμ = π` (constant) up to a
//! rotation about `π` by the *precession angle* `ψ(t)`, an elliptic integral of the third
//! kind. [`FreeRigidBodyExact`] evaluates both in closed form for every regime: rotation
//! about the largest or the smallest axis, symmetric bodies, the separatrix through the
//! middle axis and its neighbourhood, steady rotations and rest.
//!
//! # Formulas
//! Let `c` be the axis the polhode circles (the largest if `M² > 2E J_mid`, else the
//! smallest), `b` the middle one and `a` the other extreme. With
//! `N_a = M² − 2E J_a`, `N_b = M² − 2E J_b`, `N_c = 2E J_c − M²`, each written as a
//! sum over the components of `μ` so that only `N_b` (the distance to the separatrix)
//! suffers cancellation:
//!
//! ```text
//! μ_a = ± A_a cn u,   μ_b = ± A_b sn u,   μ_c = ± A_c dn u,   u = λ t + u₀,
//! A_a² = J_a N_c/(J_c − J_a),  A_b² = J_b N_c/(J_c − J_b),  A_c² = J_c N_a/(J_c − J_a),
//! λ² = (J_c − J_b) N_a/(J_a J_b J_c),  k² = (J_b − J_a) N_c/((J_c − J_b) N_a),
//! 1 − k² = (J_c − J_a) N_b/((J_c − J_b) N_a).
//! ```
//!
//! In a frame whose third axis is `π` the attitude is `R = S R_z(ψ) P(μ)`, with `P(μ)`
//! the rotation taking `μ/M` to `e_z` through the Euler angles of `μ` about axis `c`,
//! `S` constant, and
//!
//! ```text
//! ψ̇ = M/J_c + M (1/J_a − 1/J_c)/(1 − ν sn² u),   ν = J_c (J_a − J_b)/(J_a (J_c − J_b)) ≤ 0,
//! ψ(t) = M t/J_c + M (1/J_a − 1/J_c)/λ · [Π(ν; am u | k²) − Π(ν; am u₀ | k²)].
//! ```
//!
//! `Π` (and `K`) are evaluated with Carlson's symmetric integrals `R_F`, `R_J` from the
//! [`ellip`] crate; `sn, cn, dn` by the arithmetic–geometric mean ([`jacobi_elliptic`]).
//! The characteristic `ν` is never positive, so `Π` is never near its pole.
//!
//! # Accuracy
//! Every step is backward stable, so the error at time `t` is that of a perturbation of
//! the inputs by a few ulps, amplified as the motion amplifies it (see the test suite and
//! the `tests` crate for the measured errors against 40-digit references).

use crate::error::{check_finite, MechanicsError};
use crate::inertia::Inertia;
use crate::state::State;
use lgsvi_lie::SO3;
use nalgebra::{Matrix3, Vector3};

/// The three Jacobi elliptic functions at one argument.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobiElliptic {
    /// `sn(u | m)`.
    pub sn: f64,
    /// `cn(u | m)`.
    pub cn: f64,
    /// `dn(u | m)`.
    pub dn: f64,
}

/// The Jacobi elliptic functions `sn(u | m)`, `cn(u | m)`, `dn(u | m)` for a parameter
/// `0 ≤ m ≤ 1` (`m = k²`; `m = 0` gives `sin, cos, 1`, `m = 1` gives `tanh, sech, sech`).
///
/// The argument is reduced modulo `2K(m)` and the functions evaluated by the
/// arithmetic–geometric mean (descending Landen transformation; DLMF §22.20). Against
/// 40-digit mpmath values the error is a few ulps for `|u|` up to a few periods, and grows
/// with `|u|/K` as the reduction must.
///
/// ```
/// use lgsvi_mechanics::exact::jacobi_elliptic;
/// let f = jacobi_elliptic(0.7, 0.3)?;
/// assert!((f.sn * f.sn + f.cn * f.cn - 1.0).abs() < 1e-15);
/// assert!((f.dn * f.dn + 0.3 * f.sn * f.sn - 1.0).abs() < 1e-15);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
///
/// # Errors
/// [`MechanicsError::NonFinite`] for NaN or infinite input, and
/// [`MechanicsError::InvalidSetting`] for `m` outside `[0, 1]`.
pub fn jacobi_elliptic(u: f64, m: f64) -> Result<JacobiElliptic, MechanicsError> {
    check_finite("argument u and parameter m", &[u, m])?;
    if !(0.0..=1.0).contains(&m) {
        return Err(MechanicsError::InvalidSetting {
            name: "elliptic parameter m",
            value: m.to_string(),
            reason: "the parameter m = k² must lie in [0, 1]",
        });
    }
    let m1 = 1.0 - m;
    if m1 == 0.0 {
        return Ok(separatrix_functions(u));
    }
    let quarter = complete_first_kind(m1);
    let (_, r, sign) = reduce(u, quarter);
    let f = sn_cn_dn_reduced(r, m, m1);
    Ok(JacobiElliptic {
        sn: sign * f.sn,
        cn: sign * f.cn,
        dn: f.dn,
    })
}

/// `sn, cn, dn` at `m = 1`.
fn separatrix_functions(u: f64) -> JacobiElliptic {
    let sech = 1.0 / u.cosh();
    JacobiElliptic {
        sn: u.tanh(),
        cn: sech,
        dn: sech,
    }
}

/// `K(m) = R_F(0, 1 − m, 1)` from the complementary parameter `m₁ = 1 − m > 0`.
fn complete_first_kind(m1: f64) -> f64 {
    // Arguments are finite and positive except one zero: R_F cannot fail.
    ellip::elliprf(0.0, m1, 1.0).unwrap_or(f64::NAN)
}

/// `u = 2jK + r` with `|r| ≤ K`: returns `(j, r, (−1)^j)`.
fn reduce(u: f64, quarter: f64) -> (f64, f64, f64) {
    if u.abs() <= quarter {
        return (0.0, u, 1.0);
    }
    let j = (u / (2.0 * quarter)).round();
    // One rounding for 2jK and the subtraction together.
    let r = (-2.0 * j).mul_add(quarter, u);
    let sign = if j.rem_euclid(2.0) == 0.0 { 1.0 } else { -1.0 };
    (j, r, sign)
}

/// `sn, cn, dn` by the AGM, for `0 < m < 1` given with its complement `m₁`.
fn sn_cn_dn_reduced(u: f64, m: f64, m1: f64) -> JacobiElliptic {
    const MAX_STEPS: usize = 40;
    let mut ratios = [0.0_f64; MAX_STEPS];
    let (mut a, mut b, mut c) = (1.0_f64, m1.sqrt(), m.sqrt());
    let mut steps = 0;
    while c.abs() > f64::EPSILON * a && steps < MAX_STEPS {
        let (a_next, b_next) = (0.5 * (a + b), (a * b).sqrt());
        c = 0.5 * (a - b);
        a = a_next;
        b = b_next;
        ratios[steps] = c / a;
        steps += 1;
    }
    let mut phi = u * a * f64::powi(2.0, steps as i32);
    for ratio in ratios[..steps].iter().rev() {
        phi = 0.5 * (phi + (ratio * phi.sin()).asin());
    }
    let (sn, cn) = phi.sin_cos();
    // dn² = k'² + k² cn²: a sum of non-negative terms, accurate even as k' → 0.
    let dn = m1.mul_add(1.0, m * cn * cn).sqrt();
    JacobiElliptic { sn, cn, dn }
}

/// `Π(ν; am r | m) = ∫₀^r dv / (1 − ν sn² v)` for `|r| ≤ K` (so `cn r ≥ 0`), in Carlson's
/// form `s R_F(c², d², 1) + (ν/3) s³ R_J(c², d², 1, 1 − ν s²)`.
fn third_kind(f: JacobiElliptic, nu: f64) -> f64 {
    let (s, c2, d2) = (f.sn, f.cn * f.cn, f.dn * f.dn);
    if s == 0.0 {
        return 0.0;
    }
    let rf = ellip::elliprf(c2, d2, 1.0).unwrap_or(f64::NAN);
    if nu == 0.0 {
        return s * rf;
    }
    let rj = ellip::elliprj(c2, d2, 1.0, 1.0 - nu * s * s).unwrap_or(f64::NAN);
    s * rf + nu / 3.0 * s * s * s * rj
}

/// How a free body moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Regime {
    /// `μ = 0`.
    Rest,
    /// `Ω ∥ μ`: uniform rotation about a principal axis (or any axis of a sphere, or of the
    /// equal-moment plane of a symmetric body).
    SteadyRotation,
    /// The polhode circles body axis `axis` (0, 1 or 2), the one of largest or smallest
    /// moment; `symmetric` when the other two moments are equal (then `μ` precesses
    /// uniformly).
    Polhode {
        /// The body axis circled.
        axis: usize,
        /// Whether the other two moments are equal.
        symmetric: bool,
    },
    /// Exactly on the separatrix `M² = 2E J_mid` through the middle axis: `μ(t)` tends to
    /// the middle axis as `t → ±∞` (`sn = tanh`, `cn = dn = sech`).
    Separatrix,
}

/// The closed-form elliptic solution.
#[derive(Debug, Clone, Copy)]
struct Elliptic {
    /// Body indices of the axes `a`, `b`, `c`.
    axes: [usize; 3],
    /// Signed amplitudes: `μ_a = amp[0] cn u`, `μ_b = amp[1] sn u`, `μ_c = amp[2] dn u`
    /// (momentum divided by `scale`).
    amp: [f64; 3],
    m: f64,
    m1: f64,
    /// `k' = √(1 − m)`.
    k1: f64,
    lambda: f64,
    /// `u₀ = q₀ K + w₀`: `q₀` quarter periods (0 or ±1) and the rest, `|w₀| ≤ K/2` when
    /// `q₀ ≠ 0` (see [`Elliptic::phase`]).
    q0: f64,
    w0: f64,
    /// `K(m)`, infinite on the separatrix.
    quarter: f64,
    /// Whether arguments near an odd multiple of `K` are evaluated in the shifted form.
    shifted: bool,
    /// `ν`.
    nu: f64,
    /// `ν' = (m − ν)/(1 − ν)` and the two coefficients of
    /// `∫₀^w dv/(1 − ν cd² v) = a w + b Π(ν'; am w | m)` (see [`Elliptic::phase`]).
    nu_shifted: f64,
    shifted_linear: f64,
    shifted_third: f64,
    /// Complete `Π(ν | m)` (unused on the separatrix).
    pi_complete: f64,
    /// `Π(ν; am u₀ | m)`.
    pi_u0: f64,
    /// `M / J_c`.
    precession_rate: f64,
    /// `M (1/J_a − 1/J_c) / λ`.
    precession_coefficient: f64,
    /// `|μ|` of the momentum divided by `scale`.
    norm: f64,
    /// The even power of two the inertia and momentum are divided by in the constants
    /// (`amp` and `norm` are in these units; `at` multiplies the momentum back).
    scale: f64,
    /// `S = R₀ P(μ₀)ᵀ`.
    frame: Matrix3<f64>,
}

// One value per body, never in a collection: the size of the elliptic variant is harmless.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
enum Motion {
    /// `R(t) = R₀ exp(t Ω̂)`, `μ` constant.
    Uniform,
    Elliptic(Elliptic),
}

/// The exact trajectory of a free rigid body, `ℓ = ½ ΩᵀJΩ`, from `R(0)` and `Ω(0)`.
///
/// Use it to validate integrators (every error in this project's reports for the free
/// body is measured against it) or wherever the free motion itself is wanted.
///
/// ```
/// use lgsvi_mechanics::exact::FreeRigidBodyExact;
/// use lgsvi_mechanics::Inertia;
/// use lgsvi_mechanics::lie::SO3;
/// use nalgebra::Vector3;
///
/// // The paper's rigid body.
/// let inertia = Inertia::from_principal_moments([3.3, 2.5, 3.4])?;
/// let body = FreeRigidBodyExact::new(inertia, SO3::identity(), Vector3::new(-2.0, 1.9, -1.0))?;
/// let s = body.state(10.0)?;
/// // R μ is conserved, and so are |μ| and the energy.
/// let pi0 = inertia.matrix() * Vector3::new(-2.0, 1.9, -1.0);
/// assert!((s.spatial_momentum() - pi0).norm() < 1e-13);
/// assert!((s.attitude().matrix().transpose() * s.attitude().matrix()
///     - nalgebra::Matrix3::identity()).norm() < 1e-15);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct FreeRigidBodyExact {
    inertia: Inertia,
    attitude0: SO3,
    momentum0: Vector3<f64>,
    omega0: Vector3<f64>,
    regime: Regime,
    motion: Motion,
}

impl FreeRigidBodyExact {
    /// The free motion of a body of inertia `inertia` from attitude `attitude0`
    /// (`world_from_body`) and body angular velocity `omega0`.
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] for a NaN or infinite `omega0`;
    /// [`MechanicsError::InvalidSetting`] for an inertia tensor that is not diagonal
    /// (express the body in its principal axes, [`Inertia::principal_axes`]).
    pub fn new(
        inertia: Inertia,
        attitude0: SO3,
        omega0: Vector3<f64>,
    ) -> Result<Self, MechanicsError> {
        check_finite("initial angular velocity", omega0.as_slice())?;
        if !inertia.is_diagonal() {
            return Err(MechanicsError::InvalidSetting {
                name: "inertia",
                value: format!("{:?}", inertia.matrix().as_slice()),
                reason: "the exact solution takes a diagonal tensor: express the body in its \
                         principal axes",
            });
        }
        let j = inertia.principal_moments();
        let mu = inertia.matrix() * omega0;
        let uniform = |regime| Self {
            inertia,
            attitude0,
            momentum0: mu,
            omega0,
            regime,
            motion: Motion::Uniform,
        };
        if mu == Vector3::zeros() {
            return Ok(uniform(Regime::Rest));
        }
        if mu.cross(&omega0) == Vector3::zeros() {
            return Ok(uniform(Regime::SteadyRotation));
        }
        // The motion depends on the inertia only through its ratios (Ω̇ = J⁻¹(JΩ × Ω)), so
        // the elliptic constants are formed from J and μ divided by `scale`, an even power
        // of two near the largest moment: exact (the results are the same bits wherever
        // no product over- or underflows), and a body of moments 1e-300 or 1e300 gets
        // its motion instead of overflowing constants. `at` scales the momentum back.
        let largest = j[0].max(j[1]).max(j[2]);
        let scale = 2f64.powi(2 * (largest.log2() / 2.0).round() as i32);
        let j = j.map(|x| x / scale);
        let momentum0 = mu;
        let mu = mu / scale;
        // Axes by increasing moment (stable for ties), and the signed distance
        // N_mid = M² − 2E J_mid = Σ μᵢ² (Jᵢ − J_mid)/Jᵢ to the separatrix, in the very
        // expression (and rounding) that gives N_b below, so that the regime and `k` agree.
        let mut order = [0, 1, 2];
        order.sort_by(|&p, &q| j[p].total_cmp(&j[q]));
        let (lo, mid, hi) = (order[0], order[1], order[2]);
        let n_mid =
            mu[lo] * mu[lo] * (j[lo] - j[mid]) / j[lo] + mu[hi] * mu[hi] * (j[hi] - j[mid]) / j[hi];
        // `c` is the axis the polhode circles, `a` the other extreme.
        let (a, c) = if n_mid >= 0.0 {
            (order[0], order[2])
        } else {
            (order[2], order[0])
        };
        let b = mid;
        let (ja, jb, jc) = (j[a], j[b], j[c]);
        let (ma, mb, mc) = (mu[a], mu[b], mu[c]);
        // Cancellation-free forms (each term has the sign of the whole).
        let n_a = mb * mb * (jb - ja) / jb + mc * mc * (jc - ja) / jc;
        let n_c = ma * ma * (jc - ja) / ja + mb * mb * (jc - jb) / jb;
        let n_b = n_mid;
        let amp_a = (ma * ma + mb * mb * ja * (jc - jb) / (jb * (jc - ja))).sqrt();
        let amp_b = (mb * mb + ma * ma * jb * (jc - ja) / (ja * (jc - jb))).sqrt();
        let amp_c = (mc * mc + mb * mb * jc * (jb - ja) / (jb * (jc - ja))).sqrt();
        let lambda = ((jc - jb) * n_a / (ja * jb * jc)).sqrt();
        let (m, m1) = if n_b == 0.0 {
            (1.0, 0.0)
        } else {
            let m = ((jb - ja) * n_c / ((jc - jb) * n_a)).clamp(0.0, 1.0);
            let m1 = ((jc - ja) * n_b / ((jc - jb) * n_a)).clamp(0.0, 1.0);
            (m, m1)
        };
        let symmetric = ja == jb;
        let regime = if m1 == 0.0 {
            Regime::Separatrix
        } else {
            Regime::Polhode { axis: c, symmetric }
        };
        // Signs: μ_a = α A_a cn u (α = sign μ_a(0), so that am u₀ ∈ [−π/2, π/2]),
        // μ_c = γ A_c dn u, μ_b = α β A_b sn u with β fixed by Euler's equation for μ̇_a:
        // β = ε γ sign(J_c − J_b), ε the sign of the permutation (a, b, c).
        let alpha = if ma < 0.0 { -1.0 } else { 1.0 };
        let gamma = if mc < 0.0 { -1.0 } else { 1.0 };
        let epsilon = if (a + 1) % 3 == b { 1.0 } else { -1.0 };
        let beta = epsilon * gamma * (jc - jb).signum();
        let amp = [alpha * amp_a, alpha * beta * amp_b, gamma * amp_c];
        // u₀ = q₀ K + w₀. Near an odd multiple of K (μ near the middle axis, where a body
        // close to the separatrix spends most of its time) sn u → ±1 and cn u, dn u are
        // O(k'): an absolute error of ε in the amplitude am u would be a relative error
        // ε/k' in them. There the shifted form u = ±K + w is used, whose functions of w are
        // O(1) (Elliptic::phase); it is chosen when |u₀| > K/2, i.e. cn²u₀ (1 + k') < k'.
        let (sn0, cn0) = (mb / amp[1], ma / amp[0]);
        let k1 = m1.sqrt();
        let shifted = m > 0.5 && m1 > 0.0;
        let (q0, s0, c0) = if shifted && cn0 * cn0 * (1.0 + k1) < k1 * (sn0 * sn0 + cn0 * cn0) {
            // sn w₀ ∝ −σ μ_a/amp_a, cn w₀ ∝ σ k' μ_b/amp_b, σ = sign(sn u₀).
            let sigma = if sn0 < 0.0 { -1.0 } else { 1.0 };
            (sigma, -sigma * cn0, k1 * sn0.abs())
        } else {
            (0.0, sn0, cn0)
        };
        // The amplitude's sine and cosine, normalised (cn ≥ 0: |am| ≤ π/2).
        let radius = s0.hypot(c0);
        let (sin0, cos0) = (s0 / radius, c0 / radius);
        let w0 = if m1 == 0.0 {
            // atanh(sin φ₀) as asinh(tan φ₀): no cancellation in 1 − sin φ₀.
            (sin0 / cos0).asinh()
        } else {
            sin0 * ellip::elliprf(cos0 * cos0, m1.mul_add(1.0, m * cos0 * cos0), 1.0)
                .unwrap_or(f64::NAN)
        };
        let nu = jc * (ja - jb) / (ja * (jc - jb));
        let norm = mu.norm();
        let (quarter, pi_complete) = if m1 == 0.0 {
            // No period: the argument is never reduced.
            (f64::INFINITY, 0.0)
        } else {
            let quarter = complete_first_kind(m1);
            let pi_complete =
                quarter + nu / 3.0 * ellip::elliprj(0.0, m1, 1.0, 1.0 - nu).unwrap_or(f64::NAN);
            (quarter, pi_complete)
        };
        // 1 − ν cd² = (1 − ν)(1 − ν' sn²)/dn², so the integrand is
        // [m/ν' + (1 − m/ν')/(1 − ν' sn²)]/(1 − ν), with 1 − m/ν' = −ν m₁/((1 − ν) ν').
        let nu_shifted = (m - nu) / (1.0 - nu);
        let (shifted_linear, shifted_third) = if shifted {
            (
                m / (nu_shifted * (1.0 - nu)),
                -nu * m1 / ((1.0 - nu) * (1.0 - nu) * nu_shifted),
            )
        } else {
            (0.0, 0.0)
        };
        let mut elliptic = Elliptic {
            axes: [a, b, c],
            amp,
            m,
            m1,
            k1,
            lambda,
            q0,
            w0,
            quarter,
            shifted,
            nu,
            nu_shifted,
            shifted_linear,
            shifted_third,
            pi_complete,
            pi_u0: 0.0,
            precession_rate: norm / jc,
            precession_coefficient: norm * (1.0 / ja - 1.0 / jc) / lambda,
            norm,
            scale,
            frame: Matrix3::identity(),
        };
        // Π at u₀ by the very evaluation `at(0)` makes, so that ψ(0) = 0 exactly.
        elliptic.pi_u0 = elliptic.phase(q0, w0).1;
        elliptic.frame = attitude0.matrix() * elliptic.polhode_frame(&mu).transpose();
        let body = Self {
            inertia,
            attitude0,
            momentum0,
            omega0,
            regime,
            motion: Motion::Elliptic(elliptic),
        };
        let constants = [
            lambda,
            w0,
            elliptic.pi_u0,
            elliptic.pi_complete,
            elliptic.precession_coefficient,
        ];
        check_finite("elliptic constants of the free motion", &constants)?;
        Ok(body)
    }

    /// The regime of the motion.
    pub fn regime(&self) -> Regime {
        self.regime
    }

    /// The inertia.
    pub fn inertia(&self) -> Inertia {
        self.inertia
    }

    /// The period of `Ω(t)` (`4K/λ`), or `None` when `Ω` is constant or on the separatrix.
    /// (The attitude is in general not periodic.)
    pub fn period(&self) -> Option<f64> {
        match &self.motion {
            Motion::Elliptic(e) if e.m1 > 0.0 => Some(4.0 * e.quarter / e.lambda),
            _ => None,
        }
    }

    /// The conserved energy `½ ΩᵀJΩ`.
    pub fn energy(&self) -> f64 {
        0.5 * self.momentum0.dot(&self.omega0)
    }

    /// The conserved spatial momentum `π = R μ`.
    pub fn spatial_momentum(&self) -> Vector3<f64> {
        self.attitude0.matrix() * self.momentum0
    }

    /// The state at time `t` (any sign): attitude, body momentum and angular velocity.
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] for a NaN or infinite `t`.
    pub fn state(&self, t: f64) -> Result<State, MechanicsError> {
        check_finite("time", &[t])?;
        let (attitude, momentum) = match &self.motion {
            Motion::Uniform => (
                SO3::from_matrix_unchecked(
                    self.attitude0.matrix() * SO3::exp(&(self.omega0 * t)).matrix(),
                ),
                self.momentum0,
            ),
            Motion::Elliptic(e) => e.at(t),
        };
        Ok(State {
            time: t,
            configuration: attitude,
            momentum,
            velocity: self.inertia.velocity(&momentum),
        })
    }
}

impl Elliptic {
    /// `(sn, cn, dn)(u)` and `Π(ν; am u | m)` at `u = q K + v` (`q` an integer).
    ///
    /// The argument is brought to `u = 2jK + r`, and `r` evaluated directly when
    /// `|r| ≤ K/2` (or when `m ≤ 1/2`, where `dn ≥ 1/√2` and nothing is ill-conditioned);
    /// otherwise as `r = σK + w`, `|w| ≤ K/2`, through
    /// `sn(σK + w) = σ cn w/dn w`, `cn(σK + w) = −σ k' sn w/dn w`, `dn(σK + w) = k'/dn w`
    /// (DLMF 22.4.iii) and `Π(ν; am(σK + w)) = σ Π(ν) + ∫₀^w dv/(1 − ν cd² v)`, where the
    /// integrand is that of `Π(ν'; ·)` plus a constant (see the fields). Every quantity
    /// is then a product of factors with small relative error, even as `k' → 0`.
    fn phase(&self, q: f64, v: f64) -> (JacobiElliptic, f64) {
        if self.m1 == 0.0 {
            let f = separatrix_functions(v);
            return (f, third_kind(f, self.nu));
        }
        if !self.shifted {
            let (j, r, sign) = reduce(q.mul_add(self.quarter, v), self.quarter);
            let f = sn_cn_dn_reduced(r, self.m, self.m1);
            let pi = (2.0 * j).mul_add(self.pi_complete, third_kind(f, self.nu));
            return (
                JacobiElliptic {
                    sn: sign * f.sn,
                    cn: sign * f.cn,
                    dn: f.dn,
                },
                pi,
            );
        }
        // u = q K + w with |w| ≤ K/2, then q = 2j + e, e ∈ {0, 1}.
        let shift = (v / self.quarter).round();
        let q = q + shift;
        let w = (-shift).mul_add(self.quarter, v);
        let j = (0.5 * q).floor();
        let odd = q - 2.0 * j != 0.0;
        let sign = if j.rem_euclid(2.0) == 0.0 { 1.0 } else { -1.0 };
        let g = sn_cn_dn_reduced(w, self.m, self.m1);
        let (f, pi_r) = if odd {
            let shifted = self
                .shifted_linear
                .mul_add(w, self.shifted_third * third_kind(g, self.nu_shifted));
            (
                JacobiElliptic {
                    sn: g.cn / g.dn,
                    cn: -self.k1 * g.sn / g.dn,
                    dn: self.k1 / g.dn,
                },
                self.pi_complete + shifted,
            )
        } else {
            (g, third_kind(g, self.nu))
        };
        let pi = (2.0 * j).mul_add(self.pi_complete, pi_r);
        (
            JacobiElliptic {
                sn: sign * f.sn,
                cn: sign * f.cn,
                dn: f.dn,
            },
            pi,
        )
    }

    /// Attitude and body momentum at `t`.
    fn at(&self, t: f64) -> (SO3, Vector3<f64>) {
        let (functions, pi_u) = self.phase(self.q0, self.lambda.mul_add(t, self.w0));
        let [a, b, c] = self.axes;
        let mut mu = Vector3::zeros();
        mu[a] = self.amp[0] * functions.cn;
        mu[b] = self.amp[1] * functions.sn;
        mu[c] = self.amp[2] * functions.dn;
        let psi = self
            .precession_rate
            .mul_add(t, self.precession_coefficient * (pi_u - self.pi_u0));
        let (s, co) = psi.sin_cos();
        let rz = Matrix3::new(co, -s, 0.0, s, co, 0.0, 0.0, 0.0, 1.0);
        let r = self.frame * rz * self.polhode_frame(&mu);
        (SO3::from_matrix_unchecked(r), mu * self.scale)
    }

    /// `P(μ)`: the rotation taking `μ/M` to `e_z`, through the Euler angles (θ, φ) of `μ`
    /// in the right-handed frame `(c+1, c+2, c)`: `P = R_x(θ) R_z(φ) C`.
    fn polhode_frame(&self, mu: &Vector3<f64>) -> Matrix3<f64> {
        let c = self.axes[2];
        let (x, y) = ((c + 1) % 3, (c + 2) % 3);
        let rho = mu[x].hypot(mu[y]);
        let (sin_phi, cos_phi) = (mu[x] / rho, mu[y] / rho);
        let (sin_theta, cos_theta) = (rho / self.norm, mu[c] / self.norm);
        let rows = Matrix3::new(
            cos_phi,
            -sin_phi,
            0.0,
            cos_theta * sin_phi,
            cos_theta * cos_phi,
            -sin_theta,
            sin_theta * sin_phi,
            sin_theta * cos_phi,
            cos_theta,
        );
        let mut p = Matrix3::zeros();
        p.set_column(x, &rows.column(0));
        p.set_column(y, &rows.column(1));
        p.set_column(c, &rows.column(2));
        p
    }
}
