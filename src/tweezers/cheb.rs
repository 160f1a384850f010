//! Chebyshev series of a smooth function of one variable on [lo, hi]: built
//! from values at the Chebyshev–Lobatto points, evaluated by Clenshaw's
//! recurrence, differentiated term by term. The plectonemic phase's
//! optimum as a function of the torque is tabulated this way once per scene.

#[derive(Clone, Debug)]
pub struct Series {
    lo: f64,
    hi: f64,
    c: Vec<f64>,
}

/// The Chebyshev–Lobatto points of degree `n` on [lo, hi] (n + 1 points,
/// descending from hi).
pub fn points(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    (0..=n)
        .map(|k| {
            let x = (std::f64::consts::PI * k as f64 / n as f64).cos();
            0.5 * (lo + hi) + 0.5 * (hi - lo) * x
        })
        .collect()
}

impl Series {
    /// The interpolant through `values` at [`points`]`(values.len() − 1, lo, hi)`.
    pub fn interpolate(lo: f64, hi: f64, values: &[f64]) -> Self {
        let n = values.len() - 1;
        let mut c = vec![0.0; n + 1];
        for (j, cj) in c.iter_mut().enumerate() {
            let mut s = 0.0;
            for (k, v) in values.iter().enumerate() {
                let w = if k == 0 || k == n { 0.5 } else { 1.0 };
                s += w * v * (std::f64::consts::PI * (j * k) as f64 / n as f64).cos();
            }
            *cj = 2.0 * s / n as f64;
        }
        c[0] *= 0.5;
        c[n] *= 0.5;
        Series { lo, hi, c }
    }

    pub fn lo(&self) -> f64 {
        self.lo
    }

    pub fn hi(&self) -> f64 {
        self.hi
    }

    /// The value at x (Clenshaw).
    pub fn eval(&self, x: f64) -> f64 {
        let t = (2.0 * x - self.lo - self.hi) / (self.hi - self.lo);
        let (mut b1, mut b2) = (0.0, 0.0);
        for &ck in self.c.iter().skip(1).rev() {
            let b0 = 2.0 * t * b1 - b2 + ck;
            b2 = b1;
            b1 = b0;
        }
        t * b1 - b2 + self.c[0]
    }

    /// The derivative's series.
    pub fn derivative(&self) -> Self {
        let n = self.c.len() - 1;
        // c'_{k−1} = c'_{k+1} + 2k c_k (c' beyond the degree vanish), c'_0 halved,
        // then the chain rule's 2/(hi − lo).
        let mut e = vec![0.0; n + 2];
        for k in (1..=n).rev() {
            e[k - 1] = e[k + 1] + 2.0 * k as f64 * self.c[k];
        }
        e[0] *= 0.5;
        e.truncate(n.max(1));
        let s = 2.0 / (self.hi - self.lo);
        for v in e.iter_mut() {
            *v *= s;
        }
        Series { lo: self.lo, hi: self.hi, c: e }
    }
}

/// A function and its derivative sampled on a uniform grid, evaluated by
/// cubic Hermite interpolation: O(1) per evaluation where a series of
/// degree d costs O(d). Built from a series and its derivative; its error
/// is h⁴/384 · max|f''''| (h the spacing), checked against the series in
/// the tests below.
#[derive(Clone, Debug)]
pub struct Grid {
    lo: f64,
    step: f64,
    v: Vec<f64>,
    d: Vec<f64>,
}

impl Grid {
    pub fn new(f: &Series, df: &Series, intervals: usize) -> Self {
        let (lo, hi) = (f.lo, f.hi);
        let step = (hi - lo) / intervals as f64;
        let xs = (0..=intervals).map(|i| if i == intervals { hi } else { lo + step * i as f64 });
        let (v, d) = xs.map(|x| (f.eval(x), df.eval(x))).unzip();
        Grid { lo, step, v, d }
    }

    pub fn eval(&self, x: f64) -> f64 {
        let n = self.v.len() - 1;
        let u = ((x - self.lo) / self.step).max(0.0);
        let i = (u as usize).min(n - 1);
        let t = u - i as f64;
        let (t2, t3) = (t * t, t * t * t);
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        h00 * self.v[i] + h10 * self.step * self.d[i] + h01 * self.v[i + 1] + h11 * self.step * self.d[i + 1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_and_differentiates_a_smooth_function() {
        // exp(x) on [0.5, 2]: degree 20 is exact to rounding (its
        // coefficients fall below 1e-16 by degree ~15).
        let (lo, hi) = (0.5, 2.0);
        let v: Vec<f64> = points(20, lo, hi).iter().map(|x| x.exp()).collect();
        let s = Series::interpolate(lo, hi, &v);
        let d = s.derivative();
        for x in [0.5, 0.77, 1.3, 2.0] {
            assert!((s.eval(x) - x.exp()).abs() < 1e-13 * x.exp(), "{x}");
            assert!((d.eval(x) - x.exp()).abs() < 1e-11 * x.exp(), "{x}");
        }
        // The Hermite grid of 512 intervals: h⁴/384 · e² ≈ 1.7e-14.
        let g = Grid::new(&s, &d, 512);
        for k in 0..=97 {
            let x = lo + (hi - lo) * k as f64 / 97.0;
            assert!((g.eval(x) - x.exp()).abs() < 1e-12 * x.exp(), "{x}");
        }
    }
}
