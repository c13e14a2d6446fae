//! The Newton matrix's LU (`src/step/lu.rs`, compiled here from the same file) against
//! faer's `lu_in_place` at the sizes a step has: `D(n − 1)` = 21 (SO(3), `n = 8`), 33
//! (SO(3), `n = 12`), 42 (a body in space, `n = 8`) and 69 (SO(3), `n = 24`), on a
//! nonsymmetric matrix whose small diagonal makes the pivots exchange rows. Each
//! iteration copies the matrix and factors the copy.
//!
//! `cargo bench -p lgsvi-mechanics --bench lu` (add `-- --quick` for a short run).
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor;
use faer::{Mat, Par};
use nalgebra::DMatrix;

#[path = "../src/step/lu.rs"]
mod lu;

fn entry(i: usize, j: usize) -> f64 {
    (1.3 * i as f64 + 0.7 * j as f64).sin() + if i == j { 1e-3 } else { 0.0 }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("lu");
    for size in [21usize, 33, 42, 69] {
        let ours = DMatrix::from_fn(size, size, entry);
        let theirs = Mat::from_fn(size, size, entry);
        let mut perm = vec![0usize; size];
        let mut perm_inv = vec![0usize; size];
        let mut stack = MemBuffer::new(factor::lu_in_place_scratch::<usize, f64>(
            size,
            size,
            Par::Seq,
            Default::default(),
        ));
        group.bench_with_input(BenchmarkId::new("lgsvi", size), &size, |b, _| {
            b.iter(|| {
                let mut m = ours.clone();
                lu::lu_in_place(&mut m, &mut perm);
                std::hint::black_box(m)
            })
        });
        group.bench_with_input(BenchmarkId::new("faer", size), &size, |b, _| {
            b.iter(|| {
                let mut m = theirs.clone();
                factor::lu_in_place(
                    m.as_mut(),
                    &mut perm,
                    &mut perm_inv,
                    Par::Seq,
                    MemStack::new(&mut stack),
                    Default::default(),
                );
                std::hint::black_box(m)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
