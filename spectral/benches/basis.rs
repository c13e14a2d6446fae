//! Basis evaluation, values and first derivatives, at m points, for n = 8 and 32 nodes on
//! [0, h] — the shape of one integrator step (m Gauss points, n Chebyshev–Lobatto nodes).
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use lgsvi_spectral::Barycentric;
use std::hint::black_box;

fn basis(c: &mut Criterion) {
    let mut group = c.benchmark_group("basis_values_and_derivatives");
    let h = 0.5;
    for (n, m) in [(8usize, 8usize), (8, 12), (32, 32), (32, 48)] {
        let basis = Barycentric::chebyshev_lobatto(n, 0.0, h).unwrap();
        // Seeded, fixed points: the Gauss-like interior points (j + 0.5)/m · h.
        let points: Vec<f64> = (0..m).map(|j| (j as f64 + 0.5) / m as f64 * h).collect();
        let (mut phi, mut dphi) = (vec![0.0; n], vec![0.0; n]);
        group.bench_with_input(
            BenchmarkId::new(format!("n{n}"), format!("m{m}")),
            &points,
            |b, points| {
                b.iter(|| {
                    for &x in points {
                        basis
                            .basis_and_derivatives_into(black_box(x), &mut phi, &mut dphi)
                            .unwrap();
                    }
                    black_box(&dphi);
                })
            },
        );
        group.bench_with_input(
            BenchmarkId::new(format!("matrices_n{n}"), format!("m{m}")),
            &points,
            |b, points| {
                b.iter(|| {
                    basis
                        .evaluation_and_derivative_matrices(black_box(points))
                        .unwrap()
                })
            },
        );
    }
    group.finish();
}

criterion_group!(benches, basis);
criterion_main!(benches);
