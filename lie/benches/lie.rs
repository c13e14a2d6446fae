//! Per-call cost of exp, log, the Cayley transforms, A(ξ), A(ξ)⁻¹ and composition, beside
//! nalgebra's `Rotation3::new`, `UnitQuaternion::from_scaled_axis`, `scaled_axis()` and
//! products in the same run. Each iteration maps a fixed array of 4 inputs (rotation
//! angles 0.3, 1.1, 2.0, 2.9 about fixed axes) into an array: no allocation is timed.
use criterion::{criterion_group, criterion_main, Criterion};
use lgsvi_lie::{CayleyChart, ChartKind, ExpChart, So3Chart, UnscaledCayleyChart, SO3};
use nalgebra::{Rotation3, UnitQuaternion, Vector3};
use std::hint::black_box;

fn inputs() -> [Vector3<f64>; 4] {
    let axes = [
        Vector3::new(0.3, -0.5, 0.8),
        Vector3::new(-0.9, 0.1, 0.4),
        Vector3::new(0.2, 0.7, -0.6),
        Vector3::new(0.5, 0.5, 0.7),
    ];
    let angles = [0.3, 1.1, 2.0, 2.9];
    std::array::from_fn(|k| axes[k].normalize() * angles[k])
}

fn bench(c: &mut Criterion) {
    let ws = inputs();
    let rotations: [SO3; 4] = ws.map(|w| SO3::exp(&w));
    let nalgebra_rotations: [Rotation3<f64>; 4] = ws.map(Rotation3::new);
    let quaternions: [UnitQuaternion<f64>; 4] = ws.map(UnitQuaternion::from_scaled_axis);
    let mut g = c.benchmark_group("so3_per_4_calls");
    g.bench_function("lgsvi_exp", |b| {
        b.iter(|| black_box(ws).map(|w| SO3::exp(&w)))
    });
    g.bench_function("nalgebra_rotation3_new", |b| {
        b.iter(|| black_box(ws).map(Rotation3::new))
    });
    g.bench_function("nalgebra_quaternion_from_scaled_axis", |b| {
        b.iter(|| black_box(ws).map(UnitQuaternion::from_scaled_axis))
    });
    g.bench_function("lgsvi_log", |b| {
        b.iter(|| black_box(rotations).map(|r| r.log()))
    });
    g.bench_function("nalgebra_rotation3_scaled_axis", |b| {
        b.iter(|| black_box(nalgebra_rotations).map(|r| r.scaled_axis()))
    });
    g.bench_function("nalgebra_quaternion_scaled_axis", |b| {
        b.iter(|| black_box(quaternions).map(|q| q.scaled_axis()))
    });
    g.bench_function("lgsvi_cayley", |b| {
        b.iter(|| black_box(ws).map(|w| CayleyChart.rotation_matrix(&w)))
    });
    g.bench_function("lgsvi_cayley_unscaled", |b| {
        b.iter(|| black_box(ws).map(|w| UnscaledCayleyChart.rotation_matrix(&w)))
    });
    for (name, chart) in [
        ("exp", ChartKind::Exp),
        ("cayley_unscaled", ChartKind::CayleyUnscaled),
    ] {
        g.bench_function(format!("lgsvi_A_{name}"), |b| {
            b.iter(|| black_box(ws).map(|w| chart.rotation_left_differential(&w)))
        });
        g.bench_function(format!("lgsvi_A_inverse_{name}"), |b| {
            b.iter(|| black_box(ws).map(|w| chart.rotation_left_differential_inverse(&w)))
        });
    }
    g.bench_function("lgsvi_A_exp_static_dispatch", |b| {
        b.iter(|| black_box(ws).map(|w| ExpChart.rotation_left_differential(&w)))
    });
    let pairs: [(SO3, SO3); 4] = std::array::from_fn(|k| (rotations[k], rotations[3 - k]));
    let nalgebra_pairs: [(Rotation3<f64>, Rotation3<f64>); 4] =
        std::array::from_fn(|k| (nalgebra_rotations[k], nalgebra_rotations[3 - k]));
    g.bench_function("lgsvi_compose", |b| {
        b.iter(|| black_box(pairs).map(|(a, c)| a * c))
    });
    g.bench_function("nalgebra_rotation3_compose", |b| {
        b.iter(|| black_box(nalgebra_pairs).map(|(a, c)| a * c))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
