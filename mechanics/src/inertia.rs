//! Rigid-body inertia, in the standard form `J` or the paper's `J_d`.

use crate::error::MechanicsError;
use nalgebra::{Matrix3, Vector3};

/// The names of the inertia tensor's six entries as parameters of a step's linearisation
/// ([`crate::Integrator::linearize_with_parameters`]), in the order every built-in body
/// lists them first: the body-frame tensor's diagonal, then its off-diagonal entries, each
/// of which moves both of its symmetric places ([`Inertia::parameter_direction`]).
pub const INERTIA_PARAMETERS: [&str; 6] = ["J_xx", "J_yy", "J_zz", "J_xy", "J_xz", "J_yz"];

/// A body-frame inertia tensor `J`, validated: diagonal (principal axes along the body
/// axes) or full ([`Inertia::from_tensor`]).
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
    /// The principal moments: the diagonal in body-axis order for a diagonal tensor, the
    /// eigenvalues (ascending) otherwise.
    moments: [f64; 3],
    /// `J` and `J⁻¹`, for a full tensor; `None` for a diagonal one (whose formulas use
    /// the moments directly, as they always have).
    full: Option<FullTensor>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct FullTensor {
    tensor: Matrix3<f64>,
    inverse: Matrix3<f64>,
    /// Principal axes (columns), body frame.
    axes: Matrix3<f64>,
}

impl Inertia {
    /// `∂J/∂p` for the inertia parameter `index` of [`INERTIA_PARAMETERS`] (body frame):
    /// `e_a e_aᵀ` for `J_aa`, `e_a e_bᵀ + e_b e_aᵀ` for `J_ab` (the tensor stays
    /// symmetric). `None` past the sixth.
    ///
    /// ```
    /// use lgsvi_mechanics::Inertia;
    /// let d = Inertia::parameter_direction(3).unwrap(); // J_xy
    /// assert_eq!((d[(0, 1)], d[(1, 0)], d[(0, 0)]), (1.0, 1.0, 0.0));
    /// ```
    pub fn parameter_direction(index: usize) -> Option<Matrix3<f64>> {
        let (a, b) = *[(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)].get(index)?;
        let mut d = Matrix3::zeros();
        d[(a, b)] = 1.0;
        d[(b, a)] = 1.0;
        Some(d)
    }

    /// From the standard principal moments `J = diag(a, b, c)`.
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] or [`MechanicsError::InvalidInertia`] (a moment not
    /// positive, `J_i > J_j + J_k`, or a moment below `ε` times the largest).
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
        // A moment below ε times the largest is zero to double precision: the spin about
        // that axis, J⁻¹μ, has no scale the others can be compared with (the step's
        // equations overflow or lose every digit), which no smaller step mends.
        let (least, most) = moments
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, m), &x| (l.min(x), m.max(x)));
        if least < f64::EPSILON * most {
            return Err(MechanicsError::InvalidInertia {
                moments,
                reason: format!(
                    "the smallest principal moment {least:e} is below ε times the largest \
                     ({most:e}): double precision cannot resolve the spin about that axis; \
                     give it at least {:e}, or model the body without that rotation",
                    f64::EPSILON * most
                ),
            });
        }
        Ok(Self {
            moments,
            full: None,
        })
    }

    /// From a full body-frame tensor `J` (symmetric, positive definite, its eigenvalues
    /// obeying the triangle inequality). A tensor with zero off-diagonal entries is the
    /// same as [`Inertia::from_principal_moments`] of its diagonal.
    ///
    /// ```
    /// use lgsvi_mechanics::Inertia;
    /// use nalgebra::Matrix3;
    /// let j = Matrix3::new(3.0, 0.4, -0.2, 0.4, 2.6, 0.3, -0.2, 0.3, 3.3);
    /// let inertia = Inertia::from_tensor(j)?;
    /// assert!((inertia.matrix() - j).amax() == 0.0);
    /// let w = nalgebra::Vector3::new(0.1, -0.2, 0.3);
    /// assert!((inertia.velocity(&(j * w)) - w).amax() < 1e-15);
    /// // Not symmetric, not positive definite, not a mass distribution:
    /// assert!(Inertia::from_tensor(Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)).is_err());
    /// assert!(Inertia::from_tensor(Matrix3::new(1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0)).is_err());
    /// assert!(Inertia::from_tensor(Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 1.0, 3.0))).is_err());
    /// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
    /// ```
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`]; [`MechanicsError::InvalidInertia`] for a tensor that
    /// is not symmetric (beyond 8 ulps of its largest entry), not positive definite, or
    /// whose principal moments break `J_i ≤ J_j + J_k`.
    pub fn from_tensor(tensor: Matrix3<f64>) -> Result<Self, MechanicsError> {
        crate::error::check_finite("inertia tensor", tensor.as_slice())?;
        let size = tensor.amax();
        let asymmetry = (tensor - tensor.transpose()).amax();
        let diagonal = [tensor.m11, tensor.m22, tensor.m33];
        if asymmetry > 8.0 * f64::EPSILON * size {
            return Err(MechanicsError::InvalidInertia {
                moments: diagonal,
                reason: format!(
                    "the tensor is not symmetric (|J − Jᵀ| = {asymmetry:e}); give the nine \
                     entries of a symmetric matrix, row by row"
                ),
            });
        }
        if (0..3).all(|i| (0..3).all(|j| i == j || tensor[(i, j)] == 0.0)) {
            return Self::from_principal_moments(diagonal);
        }
        let symmetric = (tensor + tensor.transpose()) * 0.5;
        let eigen = symmetric.symmetric_eigen();
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
        let moments = order.map(|k| eigen.eigenvalues[k]);
        if moments[0] <= 0.0 {
            return Err(MechanicsError::InvalidInertia {
                moments,
                reason: "the tensor is not positive definite (a principal moment is not \
                         positive)"
                    .into(),
            });
        }
        // Validates the principal moments (positivity, triangle inequality).
        Self::from_principal_moments(moments)?;
        let axes = Matrix3::from_columns(&order.map(|k| eigen.eigenvectors.column(k).into_owned()));
        let inverse = symmetric
            .try_inverse()
            .ok_or_else(|| MechanicsError::InvalidInertia {
                moments,
                reason: "the tensor is singular".into(),
            })?;
        Ok(Self {
            moments,
            full: Some(FullTensor {
                tensor: symmetric,
                inverse,
                axes,
            }),
        })
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

    /// The standard principal moments `(J₁, J₂, J₃)`: the diagonal of a diagonal tensor
    /// (in body-axis order), the eigenvalues of a full one (ascending, along
    /// [`Inertia::principal_axes`]).
    pub fn principal_moments(&self) -> [f64; 3] {
        self.moments
    }

    /// Whether the tensor is diagonal in the body frame.
    pub fn is_diagonal(&self) -> bool {
        self.full.is_none()
    }

    /// The principal axes (columns, body frame): the identity for a diagonal tensor.
    pub fn principal_axes(&self) -> Matrix3<f64> {
        self.full.map_or(Matrix3::identity(), |f| f.axes)
    }

    /// `J Ω`.
    pub fn momentum(&self, omega: &Vector3<f64>) -> Vector3<f64> {
        match &self.full {
            None => Vector3::from(self.moments).component_mul(omega),
            Some(f) => f.tensor * omega,
        }
    }

    /// The paper's `J_d = ½ tr(J) I − J` (of the principal moments, for a full tensor).
    pub fn paper_jd(&self) -> [f64; 3] {
        let half_trace = 0.5 * (self.moments[0] + self.moments[1] + self.moments[2]);
        self.moments.map(|m| half_trace - m)
    }

    /// `J` as a matrix (body frame).
    pub fn matrix(&self) -> Matrix3<f64> {
        match &self.full {
            None => Matrix3::from_diagonal(&Vector3::from(self.moments)),
            Some(f) => f.tensor,
        }
    }

    /// `J⁻¹ μ`.
    pub fn velocity(&self, momentum: &Vector3<f64>) -> Vector3<f64> {
        if let Some(f) = &self.full {
            return f.inverse * momentum;
        }
        Vector3::new(
            momentum.x / self.moments[0],
            momentum.y / self.moments[1],
            momentum.z / self.moments[2],
        )
    }
}
