//! Per-call cost of exp, log, the Cayley transforms, A(ξ), A(ξ)⁻¹ and composition, beside
//! nalgebra's `Rotation3::new`, `UnitQuaternion::from_scaled_axis`, `scaled_axis()` and
//! products, in the same run. Each iteration runs over 1000 fixed inputs (rotation angles
//! spread over (0, 2.9] about varying axes), so criterion's "thrpt" is calls per second
//! and time / 1000 is the cost per call; nothing is allocated inside the timed loop.
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use lgsvi_lie::{CayleyChart, ChartKind, ExpChart, So3Chart, UnscaledCayleyChart, SO3};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use std::hint::black_box;

const N: usize = 1000;

fn inputs() -> Vec<Vector3<f64>> {
    (0..N)
        .map(|i| {
            let angle = 0.001 + 2.899 * i as f64 / (N - 1) as f64;
            let k = i as f64;
            Vector3::new(k.sin(), (1.3 * k).cos(), 0.5).normalize() * angle
        })
        .collect()
}

/// Sums one entry of each result so that no call can be optimised away.
fn run<X, Y>(items: &[X], f: impl Fn(&X) -> Y, pick: impl Fn(&Y) -> f64) -> f64 {
    items.iter().map(|x| pick(&f(black_box(x)))).sum()
}

fn bench(c: &mut Criterion) {
    let ws = inputs();
    let rotations: Vec<SO3> = ws.iter().map(SO3::exp).collect();
    let nalgebra_rotations: Vec<Rotation3<f64>> = ws.iter().map(|w| Rotation3::new(*w)).collect();
    let quaternions: Vec<UnitQuaternion<f64>> = ws
        .iter()
        .map(|w| UnitQuaternion::from_scaled_axis(*w))
        .collect();
    let m01 = |m: &Matrix3<f64>| m[(0, 1)];
    let mut g = c.benchmark_group("so3_1000_calls");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("lgsvi_exp", |b| {
        b.iter(|| run(&ws, SO3::exp, |r| r.matrix()[(0, 1)]))
    });
    g.bench_function("nalgebra_rotation3_new", |b| {
        b.iter(|| run(&ws, |w| Rotation3::new(*w), |r| r.matrix()[(0, 1)]))
    });
    g.bench_function("nalgebra_quaternion_from_scaled_axis", |b| {
        b.iter(|| run(&ws, |w| UnitQuaternion::from_scaled_axis(*w), |q| q.w))
    });
    g.bench_function("lgsvi_log", |b| {
        b.iter(|| run(&rotations, SO3::log, |v| v.x))
    });
    g.bench_function("nalgebra_rotation3_scaled_axis", |b| {
        b.iter(|| run(&nalgebra_rotations, Rotation3::scaled_axis, |v| v.x))
    });
    g.bench_function("nalgebra_quaternion_scaled_axis", |b| {
        b.iter(|| run(&quaternions, UnitQuaternion::scaled_axis, |v| v.x))
    });
    g.bench_function("lgsvi_cayley", |b| {
        b.iter(|| run(&ws, |w| CayleyChart.rotation_matrix(w), m01))
    });
    g.bench_function("lgsvi_cayley_unscaled", |b| {
        b.iter(|| run(&ws, |w| UnscaledCayleyChart.rotation_matrix(w), m01))
    });
    g.bench_function("lgsvi_A_exp", |b| {
        b.iter(|| run(&ws, |w| ExpChart.rotation_left_differential(w), m01))
    });
    g.bench_function("lgsvi_A_inverse_exp", |b| {
        b.iter(|| run(&ws, |w| ExpChart.rotation_left_differential_inverse(w), m01))
    });
    g.bench_function("lgsvi_A_cayley_unscaled", |b| {
        b.iter(|| {
            run(
                &ws,
                |w| UnscaledCayleyChart.rotation_left_differential(w),
                m01,
            )
        })
    });
    g.bench_function("lgsvi_A_inverse_cayley_unscaled", |b| {
        b.iter(|| {
            run(
                &ws,
                |w| UnscaledCayleyChart.rotation_left_differential_inverse(w),
                m01,
            )
        })
    });
    let kind = black_box(ChartKind::Exp);
    g.bench_function("lgsvi_A_exp_run_time_chart_choice", |b| {
        b.iter(|| run(&ws, |w| kind.rotation_left_differential(w), m01))
    });
    let pairs: Vec<(SO3, SO3)> = rotations
        .iter()
        .zip(rotations.iter().rev())
        .map(|(a, b)| (*a, *b))
        .collect();
    let nalgebra_pairs: Vec<(Rotation3<f64>, Rotation3<f64>)> = nalgebra_rotations
        .iter()
        .zip(nalgebra_rotations.iter().rev())
        .map(|(a, b)| (*a, *b))
        .collect();
    g.bench_function("lgsvi_compose", |b| {
        b.iter(|| run(&pairs, |(a, c)| *a * *c, |r| r.matrix()[(0, 1)]))
    });
    g.bench_function("nalgebra_rotation3_compose", |b| {
        b.iter(|| run(&nalgebra_pairs, |(a, c)| a * c, |r| r.matrix()[(0, 1)]))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
