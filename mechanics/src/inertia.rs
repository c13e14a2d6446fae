//! Rigid-body inertia, in the standard form `J` or the paper's `J_d`.

use crate::error::MechanicsError;
use nalgebra::{Matrix3, Vector3};

/// A body-frame inertia tensor `J` (principal axes along the body axes), validated.
///
/// Two conventions are accepted, and every constructor says which it takes:
/// - the **standard** inertia `J` (kinetic energy `½ΩᵀJΩ`):
///   [`Inertia::from_principal_moments`];
/// - the paper's **nonstandard** `J_d` (`L = tr(Ṙᵀ R J_d Rᵀ Ṙ)`), related by
///   `J = tr(J_d) I − J_d`: [`Inertia::from_paper_jd`].
///
/// A physical body has positive moments obeying the triangle inequality
/// `J_i ≤ J_j + J_k` (equivalently, positive `J_d`); anything else is refused.
///
/// ```
/// use lgsvi_mechanics::Inertia;
/// let j = Inertia::from_paper_jd([1.3, 2.1, 1.2])?;
/// // J = tr(J_d) I − J_d = (3.3, 2.5, 3.4), to rounding (1.2 + 2.1 is not exactly 3.3 in binary).
/// let expected = [3.3, 2.5, 3.4];
/// assert!(j.principal_moments().iter().zip(expected).all(|(a, b)| (a - b).abs() <= 1e-15));
/// assert!(Inertia::from_principal_moments([1.0, 1.0, 3.0]).is_err()); // 3 > 1 + 1
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertia {
    moments: [f64; 3],
}

impl Inertia {
    /// From the standard principal moments `J = diag(a, b, c)`.
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] or [`MechanicsError::InvalidInertia`] (a moment not
    /// positive, or `J_i > J_j + J_k`).
    pub fn from_principal_moments(moments: [f64; 3]) -> Result<Self, MechanicsError> {
        crate::error::check_finite("inertia", &moments)?;
        if moments.iter().any(|&m| m <= 0.0) {
            return Err(MechanicsError::InvalidInertia {
                moments,
                reason: "every principal moment must be positive".into(),
            });
        }
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            // The triangle inequality with a relative slack of a few ulps, so that a
            // body converted from a flat J_d (a disc or a rod's limit) is not refused
            // for rounding.
            if moments[i] > (moments[j] + moments[k]) * (1.0 + 4.0 * f64::EPSILON) {
                return Err(MechanicsError::InvalidInertia {
                    moments,
                    reason: format!(
                        "J{} = {} exceeds J{} + J{} = {}: no mass distribution has this inertia \
                         (triangle inequality); did you pass the paper's J_d as J?",
                        i + 1,
                        moments[i],
                        j + 1,
                        k + 1,
                        moments[j] + moments[k]
                    ),
                });
            }
        }
        Ok(Self { moments })
    }

    /// From the paper's `J_d = diag(a, b, c)`: `J = tr(J_d) I − J_d`.
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] or [`MechanicsError::InvalidInertia`] (an entry of
    /// `J_d` not positive).
    pub fn from_paper_jd(jd: [f64; 3]) -> Result<Self, MechanicsError> {
        crate::error::check_finite("inertia J_d", &jd)?;
        if jd.iter().any(|&m| m <= 0.0) {
            return Err(MechanicsError::InvalidInertia {
                moments: jd,
                reason: "every entry of the paper's J_d must be positive".into(),
            });
        }
        // J_i = tr(J_d) − (J_d)_i = (J_d)_j + (J_d)_k: one rounding, not two.
        Self::from_principal_moments([jd[1] + jd[2], jd[0] + jd[2], jd[0] + jd[1]])
    }

    /// The standard principal moments `(J₁, J₂, J₃)`.
    pub fn principal_moments(&self) -> [f64; 3] {
        self.moments
    }

    /// The paper's `J_d = ½ tr(J) I − J`.
    pub fn paper_jd(&self) -> [f64; 3] {
        let half_trace = 0.5 * (self.moments[0] + self.moments[1] + self.moments[2]);
        self.moments.map(|m| half_trace - m)
    }

    /// `J` as a matrix.
    pub fn matrix(&self) -> Matrix3<f64> {
        Matrix3::from_diagonal(&Vector3::from(self.moments))
    }

    /// `J⁻¹ μ`.
    pub fn velocity(&self, momentum: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            momentum.x / self.moments[0],
            momentum.y / self.moments[1],
            momentum.z / self.moments[2],
        )
    }
}
