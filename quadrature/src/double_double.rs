//! Double-double arithmetic: an unevaluated sum `hi + lo`, about 32 significant digits,
//! for the one evaluation per node that finds a root below an ulp.

/// An unevaluated sum `hi + lo` with `|lo| ≤ ulp(hi)/2`: about 32 significant digits.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DoubleDouble {
    pub hi: f64,
    pub lo: f64,
}

impl DoubleDouble {
    pub(crate) const fn from_f64(x: f64) -> Self {
        Self { hi: x, lo: 0.0 }
    }

    fn renormalised(hi: f64, lo: f64) -> Self {
        let s = hi + lo;
        Self {
            hi: s,
            lo: lo - (s - hi),
        }
    }

    /// Knuth's error-free sum of the leading parts, plus the trailing parts.
    pub(crate) fn add(self, other: Self) -> Self {
        let s = self.hi + other.hi;
        let bb = s - self.hi;
        let err = (self.hi - (s - bb)) + (other.hi - bb);
        Self::renormalised(s, err + self.lo + other.lo)
    }

    pub(crate) fn sub(self, other: Self) -> Self {
        self.add(Self {
            hi: -other.hi,
            lo: -other.lo,
        })
    }

    /// Product with a double; the leading product's error is exact by a fused multiply-add.
    pub(crate) fn mul_f64(self, y: f64) -> Self {
        let p = self.hi * y;
        let err = self.hi.mul_add(y, -p);
        Self::renormalised(p, err + self.lo * y)
    }

    pub(crate) fn div_f64(self, y: f64) -> Self {
        let q = self.hi / y;
        let prod = Self::from_f64(q).mul_f64(y);
        let rest = self.sub(prod);
        Self::renormalised(q, (rest.hi + rest.lo) / y)
    }

    pub(crate) fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// Product; the leading product's error is exact by a fused multiply-add.
    pub(crate) fn mul(self, o: Self) -> Self {
        let p = self.hi * o.hi;
        let err = self.hi.mul_add(o.hi, -p);
        Self::renormalised(p, err + (self.hi * o.lo + self.lo * o.hi))
    }

    /// Product with a power of two (exact).
    pub(crate) fn scale(self, power_of_two: f64) -> Self {
        Self {
            hi: self.hi * power_of_two,
            lo: self.lo * power_of_two,
        }
    }

    pub(crate) fn div(self, o: Self) -> Self {
        let q = self.hi / o.hi;
        let rest = self.sub(o.mul(Self::from_f64(q)));
        Self::renormalised(q, rest.hi / o.hi)
    }

    /// Square root: the double's, with one Newton correction from the exact residual.
    pub(crate) fn sqrt(self) -> Self {
        let s = self.hi.sqrt();
        if s == 0.0 {
            return Self::from_f64(0.0);
        }
        let residual = s.mul_add(-s, self.hi) + self.lo;
        Self::renormalised(s, residual / (2.0 * s))
    }
}
