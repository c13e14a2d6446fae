//! One step of the integrator (case A of the paper: the free rigid body, h = 0.5, exact
//! matching) for n = 4, 8, 12, 16, 24 nodes, exp and the paper's unscaled Cayley chart;
//! and at h = 1, n = 10, 11 in the exp chart, the settings `lgsvi bench` finds fastest for
//! case A at errors of 1e-10 … 1e-12 over T = 100.
//! The state advances from one iteration to the next, so the cost is averaged over the
//! trajectory.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use lgsvi_mechanics::lie::{ChartKind, SO3};
use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
use nalgebra::Vector3;

fn bench(c: &mut Criterion) {
    let inertia = Inertia::from_paper_jd([1.3, 2.1, 1.2]).unwrap();
    let case_a = |settings: StepSettings| {
        Integrator::new(
            RigidBody::new(inertia),
            settings,
            SO3::identity(),
            Vector3::new(-2.0, 1.9, -1.0),
        )
        .unwrap()
    };
    let mut group = c.benchmark_group("step_case_a_h0.5");
    for chart in [ChartKind::Exp, ChartKind::CayleyUnscaled] {
        for n in [4usize, 8, 12, 16, 24] {
            let mut integrator = case_a(StepSettings::new(0.5, n).unwrap().with_chart(chart));
            group.bench_function(BenchmarkId::new(chart.to_string(), n), |b| {
                b.iter(|| integrator.step().unwrap())
            });
        }
    }
    group.finish();
    let mut group = c.benchmark_group("step_case_a_h1");
    for n in [10usize, 11] {
        let mut integrator = case_a(StepSettings::new(1.0, n).unwrap());
        group.bench_function(BenchmarkId::new("exp", n), |b| {
            b.iter(|| integrator.step().unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
