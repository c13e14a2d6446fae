//! Constructors from user data and conversions to and from nalgebra, glam and serde.

mod common;

use common::EPS;
use lgsvi_lie::{LieError, LieGroup, SE3, SO3};
use nalgebra::{Isometry3, Matrix3, Matrix4, Rotation3, UnitQuaternion, Vector3, Vector6};

fn sample() -> SO3 {
    SO3::exp(&Vector3::new(0.4, -1.3, 0.8))
}

#[test]
fn checked_construction_refuses_what_is_not_a_rotation() {
    let r = *sample().matrix();
    assert!(SO3::try_from_matrix(r).is_ok());
    let mut nan = r;
    nan[(1, 2)] = f64::NAN;
    assert!(matches!(
        SO3::try_from_matrix(nan),
        Err(LieError::NonFinite { .. })
    ));
    let scaled = r * (1.0 + 1e-6);
    let err = SO3::try_from_matrix(scaled).unwrap_err();
    assert!(matches!(err, LieError::NotOrthogonal { .. }));
    assert!(
        err.to_string().contains("from_matrix_orthonormalized"),
        "{err}"
    );
    assert!(SO3::try_from_matrix_with_tolerance(scaled, 1e-5).is_ok());
    assert!(matches!(
        SO3::try_from_matrix(-r),
        Err(LieError::NotProperRotation { .. })
    ));
    // Orthonormalising: the nearest rotation to R + noise is within the noise of R.
    let noisy = r + Matrix3::new(1e-7, -2e-7, 0.0, 3e-7, 0.0, 1e-7, 0.0, -1e-7, 2e-7);
    let fixed = SO3::from_matrix_orthonormalized(noisy).unwrap();
    assert!(fixed.orthogonality_error() <= 8.0 * EPS);
    assert!((fixed.matrix() - r).amax() < 1e-6);
    assert!(matches!(
        SO3::from_matrix_orthonormalized(Matrix3::from_diagonal(&Vector3::new(1.0, 0.0, 0.0))),
        Err(LieError::NotProperRotation { .. }) | Err(LieError::Degenerate { .. })
    ));
    assert!(matches!(
        SO3::from_matrix_orthonormalized(Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0))),
        Err(LieError::NotProperRotation { .. })
    ));
    // Quaternions.
    assert!(matches!(
        SO3::try_from_quaternion_wxyz([0.0; 4]),
        Err(LieError::ZeroQuaternion { .. })
    ));
    assert!(matches!(
        SO3::try_from_quaternion_wxyz([f64::INFINITY, 0.0, 0.0, 0.0]),
        Err(LieError::NonFinite { .. })
    ));
    let q = sample().quaternion_wxyz();
    let twice = SO3::try_from_quaternion_wxyz(q.map(|x| 2.0 * x)).unwrap();
    assert!((twice.matrix() - sample().matrix()).amax() <= 8.0 * EPS);
    // SE(3) homogeneous matrices.
    let g = SE3::new(sample(), Vector3::new(1.0, 2.0, 3.0));
    assert_eq!(SE3::try_from_matrix(g.to_matrix()).unwrap(), g);
    let mut bad = g.to_matrix();
    bad[(3, 0)] = 0.1;
    assert!(SE3::try_from_matrix(bad).is_err());
    assert!(SE3::try_from_matrix(Matrix4::from_element(f64::NAN)).is_err());
}

#[test]
fn nalgebra_round_trips() {
    let r = sample();
    let rot: Rotation3<f64> = r.into();
    assert_eq!(SO3::from(rot), r);
    let q: UnitQuaternion<f64> = r.into();
    assert!(q.w >= 0.0);
    assert!((q.to_rotation_matrix().matrix() - r.matrix()).amax() <= 8.0 * EPS);
    assert!((SO3::from(q).matrix() - r.matrix()).amax() <= 8.0 * EPS);
    // Our exp agrees with nalgebra's: an independent implementation.
    let w = Vector3::new(0.4, -1.3, 0.8);
    assert!((Rotation3::new(w).matrix() - r.matrix()).amax() <= 8.0 * EPS);
    assert!((UnitQuaternion::from_scaled_axis(w).scaled_axis() - r.log()).amax() <= 16.0 * EPS);
    let g = SE3::exp(&Vector6::new(0.1, 0.2, -0.3, 1.0, -1.0, 2.0));
    let iso: Isometry3<f64> = g.into();
    let back = SE3::from(iso);
    assert!((back.to_matrix() - g.to_matrix()).amax() <= 8.0 * EPS);
    let p = Vector3::new(0.3, 0.2, -0.7);
    assert!((iso.transform_point(&p.into()).coords - g.act(&p)).amax() <= 8.0 * EPS);
    approx::assert_relative_eq!(back, g, epsilon = 1e-14);
}

#[cfg(feature = "glam")]
#[test]
fn glam_round_trips() {
    use glam::{DAffine3, DMat3, DQuat, DVec3};
    let r = sample();
    let m: DMat3 = r.into();
    // glam stores columns: column 0 is R e₀.
    assert_eq!(m.x_axis.x, r.matrix()[(0, 0)]);
    assert_eq!(m.x_axis.y, r.matrix()[(1, 0)]);
    assert_eq!(SO3::try_from(m).unwrap(), r);
    let q: DQuat = r.into();
    let v = DVec3::new(0.1, 0.2, 0.3);
    let ours = r.act(&Vector3::new(0.1, 0.2, 0.3));
    let theirs = q * v;
    assert!(
        (theirs.x - ours.x).abs() + (theirs.y - ours.y).abs() + (theirs.z - ours.z).abs() < 1e-15
    );
    assert!((SO3::try_from(q).unwrap().matrix() - r.matrix()).amax() <= 8.0 * EPS);
    assert!(SO3::try_from(DMat3::from_diagonal(DVec3::new(1.0, 2.0, 1.0))).is_err());
    let g = SE3::new(r, Vector3::new(1.0, 2.0, 3.0));
    let a: DAffine3 = g.into();
    let p = a.transform_point3(v);
    let ours = g.act(&Vector3::new(0.1, 0.2, 0.3));
    assert!((p.x - ours.x).abs() + (p.y - ours.y).abs() + (p.z - ours.z).abs() < 1e-14);
    assert_eq!(SE3::try_from(a).unwrap(), g);
    assert!(SE3::try_from(DAffine3::from_scale(DVec3::splat(2.0))).is_err());
}

#[cfg(feature = "serde")]
#[test]
fn serde_round_trips_row_major() {
    let r = SO3::about_z(std::f64::consts::FRAC_PI_2);
    let json = serde_json::to_string(&r).unwrap();
    let values: Vec<f64> = serde_json::from_str(&json).unwrap();
    assert_eq!(values.len(), 9);
    // Row-major: entry (0, 1) of a 90° rotation about z is −1.
    assert!((values[1] + 1.0).abs() < 1e-15);
    assert_eq!(serde_json::from_str::<SO3>(&json).unwrap(), r);
    let err = serde_json::from_str::<SO3>("[1,0,0,0,1,0,0,0,2]").unwrap_err();
    assert!(err.to_string().contains("not a rotation"), "{err}");
    let g = SE3::new(r, Vector3::new(1.0, 2.0, 3.0));
    let json = serde_json::to_string(&g).unwrap();
    assert!(json.contains("\"translation\":[1.0,2.0,3.0]"), "{json}");
    assert_eq!(serde_json::from_str::<SE3>(&json).unwrap(), g);
    assert!(serde_json::from_str::<SE3>(
        r#"{"rotation":[1,0,0,0,1,0,0,0,1],"translation":[0,0,0],"scale":2}"#
    )
    .is_err());
}
