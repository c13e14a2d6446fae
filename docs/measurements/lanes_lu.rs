//! How much four members' Newton-matrix LU and triangular solves gain in SIMD lanes across
//! members (#56 item 5), measured before building lanes into the step.
//!
//! The scalar side is the step's own kernels, copied as they are (`mechanics/src/step/lu.rs`:
//! partial pivoting, two pivots a pass, the AVX rank-two update; `newton::substitute`), run
//! for four members one after another as lgsvi runs them. The lane side stores entry `e` of
//! member `l` at `data[e][l]` and does the same operations in the same order in each lane
//! (pivot search and row exchanges per lane), so that each member's factors, permutation and
//! solution are the scalar ones bit for bit: the program checks that. Timed: one
//! factorisation and three solves per member (a case-A step at h = 1, n = 10 does 1 and 3),
//! medians of 7 alternating runs.
//!
//! ```text
//! rustc -O -C target-feature=+avx,+avx2,+fma -o /tmp/lanes_lu docs/measurements/lanes_lu.rs
//! /tmp/lanes_lu 18 27 45
//! ```
//!
//! Sizes are the step's unknowns `3(n − 1)`: 18 at n = 7, 27 at n = 10, 45 at n = 16. The
//! results are in `docs/notes/montecarlo.md`.
use std::time::Instant;

// ---------- scalar: a copy of mechanics/src/step/lu.rs and newton::substitute ----------
#[inline(always)]
fn pivot_row(column: &[f64], from: usize) -> usize {
    let mut pivot = from;
    let mut largest = column[from].abs();
    for (i, x) in column.iter().enumerate().skip(from + 1) {
        if x.abs() > largest {
            largest = x.abs();
            pivot = i;
        }
    }
    pivot
}
#[inline(always)]
fn pivot_and_scale(data: &mut [f64], size: usize, perm: &mut [usize], k: usize) {
    let pivot = pivot_row(&data[k * size..(k + 1) * size], k);
    if pivot != k {
        perm.swap(k, pivot);
        for column in data.chunks_exact_mut(size) {
            column.swap(k, pivot);
        }
    }
    let column = &mut data[k * size..(k + 1) * size];
    let inverse = 1.0 / column[k];
    for x in &mut column[k + 1..] {
        *x *= inverse;
    }
}
fn factor_columns(data: &mut [f64], size: usize, perm: &mut [usize]) {
    let mut k = 0;
    while k + 1 < size {
        pivot_and_scale(data, size, perm, k);
        {
            let (done, rest) = data.split_at_mut((k + 1) * size);
            let first = &done[k * size..];
            let second = &mut rest[..size];
            let u = second[k];
            for (x, l) in second[k + 1..].iter_mut().zip(&first[k + 1..]) {
                *x -= l * u;
            }
        }
        pivot_and_scale(data, size, perm, k + 1);
        let (done, rest) = data.split_at_mut((k + 2) * size);
        let first = &done[k * size + k + 2..(k + 1) * size];
        let second = &done[(k + 1) * size + k + 2..(k + 2) * size];
        let between = done[k * size + k + 1];
        for column in rest.chunks_exact_mut(size) {
            let u1 = column[k];
            let u2 = column[k + 1] - between * u1;
            column[k + 1] = u2;
            // SAFETY: the program is compiled with AVX enabled (header).
            unsafe { rank_two_update_avx(&mut column[k + 2..], first, second, u1, u2) }
        }
        k += 2;
    }
    if k < size {
        pivot_and_scale(data, size, perm, k);
    }
}
#[target_feature(enable = "avx")]
unsafe fn rank_two_update_avx(x: &mut [f64], l1: &[f64], l2: &[f64], u1: f64, u2: f64) {
    use std::arch::x86_64::*;
    let len = x.len();
    let (l1, l2) = (&l1[..len], &l2[..len]);
    let (v1, v2) = (_mm256_set1_pd(u1), _mm256_set1_pd(u2));
    let mut i = 0;
    while i + 4 <= len {
        unsafe {
            let a = _mm256_loadu_pd(l1.as_ptr().add(i));
            let b = _mm256_loadu_pd(l2.as_ptr().add(i));
            let y = _mm256_loadu_pd(x.as_ptr().add(i));
            let t = _mm256_add_pd(_mm256_mul_pd(a, v1), _mm256_mul_pd(b, v2));
            _mm256_storeu_pd(x.as_mut_ptr().add(i), _mm256_sub_pd(y, t));
        }
        i += 4;
    }
    for j in i..len {
        x[j] -= l1[j] * u1 + l2[j] * u2;
    }
}
fn substitute(lu: &[f64], b: &mut [f64]) {
    let size = b.len();
    let column_of = |k: usize| &lu[k * size..(k + 1) * size];
    for k in 0..size {
        let bk = b[k];
        let below = &column_of(k)[k + 1..];
        for (x, l) in b[k + 1..].iter_mut().zip(below) {
            *x -= l * bk;
        }
    }
    for k in (0..size).rev() {
        let column = column_of(k);
        b[k] /= column[k];
        let bk = b[k];
        for (x, u) in b[..k].iter_mut().zip(&column[..k]) {
            *x -= u * bk;
        }
    }
}

// ---------- lanes: four members, entry e of member l at data[e][l] ----------
type L = [f64; 4];
fn factor_lanes(data: &mut [L], size: usize, perm: &mut [[usize; 4]]) {
    let mut k = 0;
    while k + 1 < size {
        pivot_and_scale_lanes(data, size, perm, k);
        {
            let (done, rest) = data.split_at_mut((k + 1) * size);
            let first = &done[k * size..];
            let second = &mut rest[..size];
            let u = second[k];
            for (x, l) in second[k + 1..].iter_mut().zip(&first[k + 1..]) {
                for c in 0..4 {
                    x[c] -= l[c] * u[c];
                }
            }
        }
        pivot_and_scale_lanes(data, size, perm, k + 1);
        let (done, rest) = data.split_at_mut((k + 2) * size);
        let first = &done[k * size + k + 2..(k + 1) * size];
        let second = &done[(k + 1) * size + k + 2..(k + 2) * size];
        let between = done[k * size + k + 1];
        for column in rest.chunks_exact_mut(size) {
            let u1 = column[k];
            let mut u2 = [0.0; 4];
            for c in 0..4 {
                u2[c] = column[k + 1][c] - between[c] * u1[c];
            }
            column[k + 1] = u2;
            for ((x, a), b) in column[k + 2..].iter_mut().zip(first).zip(second) {
                for c in 0..4 {
                    x[c] -= a[c] * u1[c] + b[c] * u2[c];
                }
            }
        }
        k += 2;
    }
    if k < size {
        pivot_and_scale_lanes(data, size, perm, k);
    }
}
#[inline(always)]
fn pivot_and_scale_lanes(data: &mut [L], size: usize, perm: &mut [[usize; 4]], k: usize) {
    for c in 0..4 {
        let mut pivot = k;
        let mut largest = data[k * size + k][c].abs();
        for i in k + 1..size {
            let x = data[k * size + i][c].abs();
            if x > largest {
                largest = x;
                pivot = i;
            }
        }
        if pivot != k {
            let t = perm[k][c];
            perm[k][c] = perm[pivot][c];
            perm[pivot][c] = t;
            for column in data.chunks_exact_mut(size) {
                let t = column[k][c];
                column[k][c] = column[pivot][c];
                column[pivot][c] = t;
            }
        }
    }
    let column = &mut data[k * size..(k + 1) * size];
    let mut inverse = [0.0; 4];
    for c in 0..4 {
        inverse[c] = 1.0 / column[k][c];
    }
    for x in &mut column[k + 1..] {
        for c in 0..4 {
            x[c] *= inverse[c];
        }
    }
}
fn substitute_lanes(lu: &[L], b: &mut [L]) {
    let size = b.len();
    for k in 0..size {
        let bk = b[k];
        let below = &lu[k * size + k + 1..(k + 1) * size];
        for (x, l) in b[k + 1..].iter_mut().zip(below) {
            for c in 0..4 {
                x[c] -= l[c] * bk[c];
            }
        }
    }
    for k in (0..size).rev() {
        let column = &lu[k * size..(k + 1) * size];
        for c in 0..4 {
            b[k][c] /= column[k][c];
        }
        let bk = b[k];
        for (x, u) in b[..k].iter_mut().zip(&column[..k]) {
            for c in 0..4 {
                x[c] -= u[c] * bk[c];
            }
        }
    }
}

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let sizes = if sizes.is_empty() {
        vec![18, 27, 45]
    } else {
        sizes
    };
    let mut seed = 12345u64;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed as f64 / u64::MAX as f64) - 0.5
    };
    for size in sizes {
        let mats: Vec<Vec<f64>> = (0..4)
            .map(|_| {
                let mut m: Vec<f64> = (0..size * size).map(|_| rnd()).collect();
                for i in 0..size {
                    m[i * size + i] += 0.3;
                }
                m
            })
            .collect();
        let rhs: Vec<Vec<f64>> = (0..4).map(|_| (0..size).map(|_| rnd()).collect()).collect();
        // Scalar, four members one after another.
        let mut s_out = mats.clone();
        let mut s_perm = vec![vec![0usize; size]; 4];
        let mut s_x = rhs.clone();
        for l in 0..4 {
            for (i, p) in s_perm[l].iter_mut().enumerate() {
                *p = i;
            }
            factor_columns(&mut s_out[l], size, &mut s_perm[l]);
            let b: Vec<f64> = s_perm[l].iter().map(|&p| rhs[l][p]).collect();
            s_x[l] = b;
            substitute(&s_out[l], &mut s_x[l]);
        }
        // Lanes.
        let mut lanes: Vec<L> = (0..size * size)
            .map(|e| [mats[0][e], mats[1][e], mats[2][e], mats[3][e]])
            .collect();
        let mut perm: Vec<[usize; 4]> = (0..size).map(|i| [i; 4]).collect();
        factor_lanes(&mut lanes, size, &mut perm);
        let mut xl: Vec<L> = (0..size)
            .map(|i| {
                let mut v = [0.0; 4];
                for c in 0..4 {
                    v[c] = rhs[c][perm[i][c]];
                }
                v
            })
            .collect();
        substitute_lanes(&lanes, &mut xl);
        let mut same = true;
        for l in 0..4 {
            for e in 0..size * size {
                same &= lanes[e][l].to_bits() == s_out[l][e].to_bits();
            }
            for i in 0..size {
                same &= xl[i][l].to_bits() == s_x[l][i].to_bits();
                same &= perm[i][l] == s_perm[l][i];
            }
        }
        // Timing: factor + 3 solves (a step's 1 factorisation and 3 iterations), 4 members.
        let reps = 200_000 / size.max(1) * 10;
        let run_scalar = || {
            let mut work = mats.clone();
            let mut pm = vec![vec![0usize; size]; 4];
            let mut acc = 0.0;
            for l in 0..4 {
                for (i, p) in pm[l].iter_mut().enumerate() {
                    *p = i;
                }
                factor_columns(&mut work[l], size, &mut pm[l]);
                for _ in 0..3 {
                    let mut b: Vec<f64> = pm[l].iter().map(|&p| rhs[l][p]).collect();
                    substitute(&work[l], &mut b);
                    acc += b[0];
                }
            }
            acc
        };
        let lane0: Vec<L> = (0..size * size)
            .map(|e| [mats[0][e], mats[1][e], mats[2][e], mats[3][e]])
            .collect();
        let run_lanes = || {
            let mut work = lane0.clone();
            let mut pm: Vec<[usize; 4]> = (0..size).map(|i| [i; 4]).collect();
            factor_lanes(&mut work, size, &mut pm);
            let mut acc = 0.0;
            for _ in 0..3 {
                let mut b: Vec<L> = (0..size)
                    .map(|i| {
                        let mut v = [0.0; 4];
                        for c in 0..4 {
                            v[c] = rhs[c][pm[i][c]];
                        }
                        v
                    })
                    .collect();
                substitute_lanes(&work, &mut b);
                acc += b[0][0];
            }
            acc
        };
        let mut ts = Vec::new();
        let mut tl = Vec::new();
        let mut sink = 0.0;
        for _ in 0..7 {
            let t = Instant::now();
            for _ in 0..reps {
                sink += std::hint::black_box(run_scalar());
            }
            ts.push(t.elapsed().as_secs_f64());
            let t = Instant::now();
            for _ in 0..reps {
                sink += std::hint::black_box(run_lanes());
            }
            tl.push(t.elapsed().as_secs_f64());
        }
        ts.sort_by(f64::total_cmp);
        tl.sort_by(f64::total_cmp);
        println!("size {size}: bit-identical {same}; 4 members' factor + 3 solves: scalar {:.2} us, lanes {:.2} us, ratio {:.2} (medians of 7; {sink:e})",
            ts[3] / reps as f64 * 1e6, tl[3] / reps as f64 * 1e6, ts[3] / tl[3]);
    }
}
