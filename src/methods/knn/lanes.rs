//! Four f32 lanes at once for the k-NN's sums: SSE on x86-64, simd128 on wasm32 (when built with
//! it, as the page is), plain arrays elsewhere. Each lane is added, subtracted and multiplied on
//! its own with IEEE single-precision rounding (no fused multiply-add), so a sum kept in one lane
//! is bit for bit the scalar sum of the same terms in the same order. Written out because the
//! compiler left the projection's 32 running sums scalar (measured: the whole-take projection was
//! most of the k-NN's time).

#[cfg(target_arch = "x86_64")]
mod imp {
    use core::arch::x86_64::*;

    pub type V = __m128;

    #[inline(always)]
    pub fn splat(v: f32) -> V {
        // SSE is part of x86-64: the intrinsics only need it enabled, which it always is
        #[allow(unused_unsafe)]
        unsafe {
            _mm_set1_ps(v)
        }
    }

    #[inline(always)]
    pub fn load(a: &[f32; 4]) -> V {
        // four readable floats behind the reference; unaligned load
        unsafe { _mm_loadu_ps(a.as_ptr()) }
    }

    #[inline(always)]
    pub fn store(v: V, out: &mut [f32; 4]) {
        unsafe { _mm_storeu_ps(out.as_mut_ptr(), v) }
    }

    #[inline(always)]
    pub fn add(a: V, b: V) -> V {
        #[allow(unused_unsafe)]
        unsafe {
            _mm_add_ps(a, b)
        }
    }

    #[inline(always)]
    pub fn sub(a: V, b: V) -> V {
        #[allow(unused_unsafe)]
        unsafe {
            _mm_sub_ps(a, b)
        }
    }

    #[inline(always)]
    pub fn mul(a: V, b: V) -> V {
        #[allow(unused_unsafe)]
        unsafe {
            _mm_mul_ps(a, b)
        }
    }

    /// Whether every lane of `a` is at least the lane of `b` (false for NaN).
    #[inline(always)]
    pub fn all_ge(a: V, b: V) -> bool {
        #[allow(unused_unsafe)]
        unsafe {
            _mm_movemask_ps(_mm_cmpge_ps(a, b)) == 0b1111
        }
    }
}

#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod imp {
    use core::arch::wasm32::*;

    pub type V = v128;

    #[inline(always)]
    pub fn splat(v: f32) -> V {
        f32x4_splat(v)
    }

    #[inline(always)]
    pub fn load(a: &[f32; 4]) -> V {
        // sixteen readable bytes behind the reference; v128 loads need no alignment
        unsafe { v128_load(a.as_ptr() as *const v128) }
    }

    #[inline(always)]
    pub fn store(v: V, out: &mut [f32; 4]) {
        unsafe { v128_store(out.as_mut_ptr() as *mut v128, v) }
    }

    #[inline(always)]
    pub fn add(a: V, b: V) -> V {
        f32x4_add(a, b)
    }

    #[inline(always)]
    pub fn sub(a: V, b: V) -> V {
        f32x4_sub(a, b)
    }

    #[inline(always)]
    pub fn mul(a: V, b: V) -> V {
        f32x4_mul(a, b)
    }

    #[inline(always)]
    pub fn all_ge(a: V, b: V) -> bool {
        i32x4_all_true(f32x4_ge(a, b))
    }
}

#[cfg(not(any(target_arch = "x86_64", all(target_arch = "wasm32", target_feature = "simd128"))))]
mod imp {
    pub type V = [f32; 4];

    #[inline(always)]
    pub fn splat(v: f32) -> V {
        [v; 4]
    }

    #[inline(always)]
    pub fn load(a: &[f32; 4]) -> V {
        *a
    }

    #[inline(always)]
    pub fn store(v: V, out: &mut [f32; 4]) {
        *out = v;
    }

    #[inline(always)]
    pub fn add(a: V, b: V) -> V {
        std::array::from_fn(|l| a[l] + b[l])
    }

    #[inline(always)]
    pub fn sub(a: V, b: V) -> V {
        std::array::from_fn(|l| a[l] - b[l])
    }

    #[inline(always)]
    pub fn mul(a: V, b: V) -> V {
        std::array::from_fn(|l| a[l] * b[l])
    }

    #[inline(always)]
    pub fn all_ge(a: V, b: V) -> bool {
        a.iter().zip(&b).all(|(x, y)| x >= y)
    }
}

/// Four f32 lanes.
#[derive(Clone, Copy)]
pub struct F4(imp::V);

impl F4 {
    #[inline(always)]
    pub fn splat(v: f32) -> F4 {
        F4(imp::splat(v))
    }

    #[inline(always)]
    pub fn load(a: &[f32; 4]) -> F4 {
        F4(imp::load(a))
    }

    #[inline(always)]
    pub fn store(self, out: &mut [f32; 4]) {
        imp::store(self.0, out)
    }

    #[inline(always)]
    pub fn add(self, b: F4) -> F4 {
        F4(imp::add(self.0, b.0))
    }

    #[inline(always)]
    pub fn sub(self, b: F4) -> F4 {
        F4(imp::sub(self.0, b.0))
    }

    #[inline(always)]
    pub fn mul(self, b: F4) -> F4 {
        F4(imp::mul(self.0, b.0))
    }

    /// Whether every lane is at least `b`'s.
    #[inline(always)]
    pub fn all_ge(self, b: F4) -> bool {
        imp::all_ge(self.0, b.0)
    }
}

/// Four-float groups of a slice whose length is a multiple of 4.
#[inline(always)]
pub fn quads(v: &[f32]) -> impl Iterator<Item = &[f32; 4]> {
    v.chunks_exact(4).map(|c| c.try_into().expect("four floats"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_round_as_scalars_do() {
        let a = [1.0f32 / 3.0, -2.5e-8, 7.0e30, 0.1];
        let b = [3.0f32, 1.0e-8, 7.0e30, 0.2];
        let mut out = [0.0; 4];
        let (x, y) = (F4::load(&a), F4::load(&b));
        x.sub(y).mul(x).add(F4::splat(0.5)).store(&mut out);
        for l in 0..4 {
            assert_eq!(out[l].to_bits(), ((a[l] - b[l]) * a[l] + 0.5).to_bits());
        }
        assert!(x.all_ge(x) && !x.all_ge(y) && F4::splat(1.0).all_ge(F4::splat(1.0)));
        assert!(!F4::splat(f32::NAN).all_ge(F4::splat(0.0)));
    }
}
