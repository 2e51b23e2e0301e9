//! Small helpers on 3-vectors `[f64; 3]` (2D points carry z = 0), in one home for every
//! layer. Each takes its vectors by value or by reference alike.
//!
//! Entry points: [`add`], [`sub`], [`scale`], [`dot`], [`cross`], [`norm`], [`unit`](fn@unit).

use std::borrow::Borrow;

/// a + b.
#[inline]
pub fn add(a: impl Borrow<[f64; 3]>, b: impl Borrow<[f64; 3]>) -> [f64; 3] {
    let (a, b) = (a.borrow(), b.borrow());
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// a − b.
#[inline]
pub fn sub(a: impl Borrow<[f64; 3]>, b: impl Borrow<[f64; 3]>) -> [f64; 3] {
    let (a, b) = (a.borrow(), b.borrow());
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// s a.
#[inline]
pub fn scale(s: f64, a: impl Borrow<[f64; 3]>) -> [f64; 3] {
    let a = a.borrow();
    [s * a[0], s * a[1], s * a[2]]
}

/// a · b.
#[inline]
pub fn dot(a: impl Borrow<[f64; 3]>, b: impl Borrow<[f64; 3]>) -> f64 {
    let (a, b) = (a.borrow(), b.borrow());
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b.
#[inline]
pub fn cross(a: impl Borrow<[f64; 3]>, b: impl Borrow<[f64; 3]>) -> [f64; 3] {
    let (a, b) = (a.borrow(), b.borrow());
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// |a|.
#[inline]
pub fn norm(a: impl Borrow<[f64; 3]>) -> f64 {
    let a = a.borrow();
    dot(a, a).sqrt()
}

/// a / |a| (a itself when it is zero).
#[inline]
pub fn unit(a: impl Borrow<[f64; 3]>) -> [f64; 3] {
    let a = *a.borrow();
    let n = norm(a);
    if n > 0.0 {
        [a[0] / n, a[1] / n, a[2] / n]
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The helpers on hand-picked vectors: e_x × e_y = e_z, |(3, 4, 0)| = 5, by value and by
    /// reference alike.
    #[test]
    fn helpers_follow_their_definitions() {
        let (x, y) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        assert_eq!(cross(x, y), [0.0, 0.0, 1.0]);
        assert_eq!(cross(x, y), [0.0, 0.0, 1.0]);
        assert_eq!(norm([3.0, 4.0, 0.0]), 5.0);
        assert_eq!(unit([3.0, 4.0, 0.0]), [0.6, 0.8, 0.0]);
        assert_eq!(unit([0.0; 3]), [0.0; 3]);
        assert_eq!(dot(add(x, y), sub(x, y)), 0.0);
        assert_eq!(scale(2.0, y), [0.0, 2.0, 0.0]);
    }
}
