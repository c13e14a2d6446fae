//! Rule construction for m = 10, 100, 1000 (the classical weighted rules up to 10⁴: their
//! `O(m)` march), and, for the choice of eigensolver, the same Golub–Welsch eigenproblem
//! solved by nalgebra's dense symmetric eigensolver.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use lgsvi_quadrature::{
    gauss_hermite, gauss_jacobi, gauss_laguerre, gauss_legendre, gauss_lobatto, golub_welsch,
};
use std::hint::black_box;

fn construction(c: &mut Criterion) {
    let mut group = c.benchmark_group("construct");
    for m in [10usize, 100, 1000] {
        group.bench_with_input(BenchmarkId::new("gauss_legendre", m), &m, |b, &m| {
            b.iter(|| gauss_legendre(black_box(m)).unwrap())
        });
        group.bench_with_input(BenchmarkId::new("gauss_lobatto", m), &m, |b, &m| {
            b.iter(|| gauss_lobatto(black_box(m)).unwrap())
        });
    }
    for m in [100usize, 1000, 10_000] {
        group.bench_with_input(BenchmarkId::new("gauss_hermite", m), &m, |b, &m| {
            b.iter(|| gauss_hermite(black_box(m)).unwrap())
        });
        group.bench_with_input(BenchmarkId::new("gauss_laguerre", m), &m, |b, &m| {
            b.iter(|| gauss_laguerre(black_box(m), 0.5).unwrap())
        });
        group.bench_with_input(BenchmarkId::new("gauss_jacobi", m), &m, |b, &m| {
            b.iter(|| gauss_jacobi(black_box(m), 0.5, -0.5).unwrap())
        });
    }
    group.finish();
}

fn eigensolvers(c: &mut Criterion) {
    let mut group = c.benchmark_group("legendre_jacobi_eigen");
    for m in [10usize, 100, 400] {
        let off: Vec<f64> = (1..m)
            .map(|k| k as f64 / (4.0 * (k * k) as f64 - 1.0).sqrt())
            .collect();
        group.bench_with_input(
            BenchmarkId::new("tridiagonal_ql_first_row", m),
            &m,
            |b, &m| {
                b.iter(|| golub_welsch(black_box(&vec![0.0; m]), black_box(&off), 2.0).unwrap())
            },
        );
        let dense = nalgebra::DMatrix::from_fn(m, m, |i, j| {
            if i.abs_diff(j) == 1 {
                off[i.min(j)]
            } else {
                0.0
            }
        });
        group.bench_with_input(
            BenchmarkId::new("nalgebra_symmetric_eigen", m),
            &m,
            |b, _| b.iter(|| nalgebra::SymmetricEigen::new(black_box(dense.clone()))),
        );
    }
    group.finish();
}

criterion_group!(benches, construction, eigensolvers);
criterion_main!(benches);
