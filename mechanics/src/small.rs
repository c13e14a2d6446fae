//! Products of small fixed-size matrices, unrolled.
//!
//! nalgebra's `*` on `SMatrix` goes through its general `gemm`/`gemv` (column by column,
//! an `axpy` call per column of the left factor), which the compiler leaves as calls: on
//! a 6 × 6 product about 4k instructions for 216 multiply-adds (callgrind of the orbiting
//! body's step, `docs/performance.md` §5.11). [`product`] is the same sum in the same
//! order — column `j` of `a b` is `Σ_k a[:, k] b[k, j]`, `k` from 0, starting from the
//! first term — written as loops over constant bounds that the compiler unrolls and
//! vectorises: bit-identical to nalgebra's product (test below).

use nalgebra::SMatrix;

/// `a b`, as nalgebra's `a * b` to the bit.
#[inline(always)]
pub(crate) fn product<const R: usize, const K: usize, const C: usize>(
    a: &SMatrix<f64, R, K>,
    b: &SMatrix<f64, K, C>,
) -> SMatrix<f64, R, C> {
    let (a, b) = (a.as_slice(), b.as_slice());
    let mut c = SMatrix::<f64, R, C>::zeros();
    let out = c.as_mut_slice();
    for j in 0..C {
        let column = &mut out[j * R..(j + 1) * R];
        for k in 0..K {
            let bkj = b[j * K + k];
            let left = &a[k * R..(k + 1) * R];
            if k == 0 {
                for (x, l) in column.iter_mut().zip(left) {
                    *x = l * bkj;
                }
            } else {
                for (x, l) in column.iter_mut().zip(left) {
                    *x += l * bkj;
                }
            }
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::product;
    use nalgebra::SMatrix;

    /// Entries spread over many binades, so that another order of the sums or a fused
    /// multiply-add would round differently somewhere (checked: a product summed from
    /// the last `k` fails it).
    fn spread<const R: usize, const C: usize>(seed: u64) -> SMatrix<f64, R, C> {
        let mut state = seed;
        SMatrix::from_fn(|_, _| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let unit = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            unit * 10f64.powi(((state >> 3) % 9) as i32 - 4)
        })
    }

    #[test]
    fn the_unrolled_product_is_nalgebras_bit_for_bit() {
        for seed in 0..200 {
            let (a, b) = (spread::<6, 6>(seed), spread::<6, 6>(seed + 1000));
            assert_eq!(product(&a, &b), a * b, "6 × 6, seed {seed}");
            let (a, b) = (spread::<3, 3>(seed), spread::<3, 3>(seed + 1000));
            assert_eq!(product(&a, &b), a * b, "3 × 3, seed {seed}");
            let (a, b) = (spread::<3, 6>(seed), spread::<6, 4>(seed + 1000));
            assert_eq!(product(&a, &b), a * b, "3 × 6 × 4, seed {seed}");
        }
    }
}
