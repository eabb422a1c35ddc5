//! Shared helpers of the integration tests: closed forms of the particle and the knife,
//! evaluated in interval arithmetic (inari, outward rounding), so that every comparison with
//! the library is between two *enclosures* of one exact real quantity.
//!
//! Nothing here calls the library's mathematics; only `point`/`iv` are borrowed to build
//! intervals, and the interval elementary functions (`dalembert::elementary`, through the
//! `Scalar` trait: inari is built without MPFR), which tests/it/elementary.rs checks on its own.
#![allow(dead_code)]

use dalembert::elementary::asinh;
use dalembert::scalar::{iv, point, Scalar};
use inari::Interval;

pub type I = Interval;

pub fn pt(x: f64) -> I {
    point(x)
}

pub fn pts(v: &[f64]) -> Vec<I> {
    v.iter().map(|x| point(*x)).collect()
}

/// Points as the library's arguments take them.
pub fn args(v: &[f64]) -> Vec<dalembert::Interval> {
    v.iter().map(|x| dalembert::Interval::point(*x)).collect()
}

/// The library's answers as inari intervals, for arithmetic.
pub fn ia(v: &[dalembert::Interval]) -> Vec<I> {
    v.iter().map(|x| I::from(*x)).collect()
}

pub fn mids<T: Copy + Into<I>>(v: &[T]) -> Vec<f64> {
    v.iter().map(|x| (*x).into().mid()).collect()
}

/// Width relative to max(1, |x|).
pub fn rel_wid(x: impl Into<I>) -> f64 {
    let x = x.into();
    x.wid() / x.mag().max(1.0)
}

pub fn max_rel_wid<T: Copy + Into<I>>(v: &[T]) -> f64 {
    v.iter().map(|x| rel_wid(*x)).fold(0.0, f64::max)
}

/// Exact bit patterns of inputs, for reproducing failures.
pub fn bits(v: &[f64]) -> String {
    let parts: Vec<String> = v
        .iter()
        .map(|x| format!("{x:e}=0x{:016x}", x.to_bits()))
        .collect();
    format!("[{}]", parts.join(", "))
}

pub fn overlap<A: Copy + Into<I>, B: Copy + Into<I>>(a: &[A], b: &[B]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| !(*x).into().disjoint((*y).into()))
}

/// Distance between two intervals (0 when they intersect).
pub fn gap(a: impl Into<I>, b: impl Into<I>) -> f64 {
    let (a, b) = (a.into(), b.into());
    if !a.disjoint(b) {
        0.0
    } else if a.sup() < b.inf() {
        b.inf() - a.sup()
    } else {
        a.inf() - b.sup()
    }
}

/// The exact rational number num/den, enclosed.
fn q(num: f64, den: f64) -> I {
    point(num) / point(den)
}

/// `[0, x]` for x >= 0 (upper end rounded up by the interval product that produced it).
fn up_to(x: I) -> I {
    iv(0.0, x.sup())
}

/// sqrt(1 + y^2).
pub fn sq1(y: I) -> I {
    (point(1.0) + y.sqr()).sqrt()
}

/// asinh(a)/a at a single a >= 0 (1 at a = 0), enclosed.
fn asinh_over_at(a: f64) -> I {
    if a < 1e-3 {
        // asinh(w)/w = 1 - w^2/6 + 3 w^4/40 - 5 w^6/112 + ..., an alternating series whose
        // terms decrease for |w| < 1: the value lies between consecutive partial sums.
        let t = point(a).sqr();
        let p = point(1.0) - t * q(1.0, 6.0) + t.sqr() * q(3.0, 40.0);
        p - up_to(t * t.sqr() * q(5.0, 112.0))
    } else {
        asinh(point(a)) / point(a)
    }
}

/// F(w) = asinh(w)/w over a box of w. F is even and decreasing in |w|, so
/// F(w) lies in [F(mag w), F(mig w)].
pub fn asinh_over(w: I) -> I {
    let lo = asinh_over_at(w.mag()).inf();
    let hi = asinh_over_at(w.mig()).sup();
    iv(lo, hi)
}

/// r(y0, y1) = (y1 - y0) / (asinh(y1) - asinh(y0)), continuous with r = sqrt(1 + y0^2) at
/// y1 = y0, enclosed without catastrophic cancellation. `d` must enclose y1 - y0 for the same
/// real pair (it may be tighter than `y1 - y0` evaluated in intervals).
///
/// Same sign: asinh(y1) - asinh(y0) = asinh(w) with
/// w = y1 sqrt(1+y0^2) - y0 sqrt(1+y1^2) = d g, g = (y1 + y0)/(y1 sqrt(1+y0^2) + y0 sqrt(1+y1^2)),
/// so r = 1/(g F(d g)). Opposite signs: asinh(y1) and asinh(y0) have opposite signs, no
/// cancellation.
pub fn ratio(y0: I, y1: I, d: I) -> I {
    if d.inf() == 0.0 && d.sup() == 0.0 {
        return sq1(y0);
    }
    let same_sign = (y0.inf() > 0.0 && y1.inf() > 0.0) || (y0.sup() < 0.0 && y1.sup() < 0.0);
    if same_sign {
        let g = (y1 + y0) / (y1 * sq1(y0) + y0 * sq1(y1));
        point(1.0) / (g * asinh_over(d * g))
    } else {
        d / (asinh(y1) - asinh(y0))
    }
}

/// The particle's trajectory in closed form (paper eq. (nhsolution)), rewritten without the
/// division by yd0: with y(t) = y0 + u2 t, S = sqrt(1+y^2),
/// x(t) = x0 + u1 S0 t / r(y0, y(t)), z(t) = z0 + u1 S0 t (y(t) + y0)/(S(t) + S0),
/// xd(t) = u1 S0 / S(t). Valid for boxes q0, u (u = (xd0, yd0) = quasi-velocities).
pub fn particle_q(q0: &[I], u: &[I], t: f64) -> Vec<I> {
    let tt = pt(t);
    let d = u[1] * tt;
    let y = q0[1] + d;
    let s0 = sq1(q0[1]);
    let r = ratio(q0[1], y, d);
    let x = q0[0] + u[0] * s0 * tt / r;
    let z = q0[2] + u[0] * s0 * tt * (y + q0[1]) / (sq1(y) + s0);
    vec![x, y, z]
}

/// Closed-form exact retraction of the particle at f64 inputs.
#[derive(Clone, Debug)]
pub struct ParticleRet {
    /// A = (S1 - S0)/(asinh y1 - asinh y0) (= y0 at y1 = y0).
    pub a: I,
    /// h mu_d(Q0, Q1) (paper eq. (defdiscrete) times h).
    pub h_mu_d: I,
    /// The defect s = -h mu_d(Q0,Q1) / (1 + y1 A).
    pub s: I,
    /// q(h) = Q1 + N(Q1) s = (x1 - y1 s, y1, z1 + s).
    pub q1: Vec<I>,
    /// (xd0, yd0) = R^{e-} of (Q0, q(h)).
    pub u0: Vec<I>,
    /// F^- = (xd0 (1 + y0^2), yd0), F^+ = (xd0 S0 S1, yd0).
    pub p_minus: Vec<I>,
    pub p_plus: Vec<I>,
    /// The action: L = |qd|^2/2 is constant along the trajectory, l = h (xd0^2 S0^2 + yd0^2)/2.
    pub l: I,
}

/// h mu_d(Q0, Q1) = (z1 - z0) - (x1 - x0) A(y0, y1), over boxes.
pub fn particle_h_mu_d<A: Copy + Into<I>, B: Copy + Into<I>>(q0: &[A], q1: &[B]) -> I {
    let (q0, q1) = (
        q0.iter().map(|x| (*x).into()).collect::<Vec<I>>(),
        q1.iter().map(|x| (*x).into()).collect::<Vec<I>>(),
    );
    let d = q1[1] - q0[1];
    let r = ratio(q0[1], q1[1], d);
    let a = (q1[1] + q0[1]) / (sq1(q1[1]) + sq1(q0[1])) * r;
    (q1[2] - q0[2]) - (q1[0] - q0[0]) * a
}

pub fn particle_retraction(q0: &[f64], q1: &[f64], h: f64) -> ParticleRet {
    let (x0, y0, z0) = (pt(q0[0]), pt(q0[1]), pt(q0[2]));
    let (x1, y1, z1) = (pt(q1[0]), pt(q1[1]), pt(q1[2]));
    let hh = pt(h);
    let d = y1 - y0;
    let r = ratio(y0, y1, d);
    let (s0, s1) = (sq1(y0), sq1(y1));
    // S1 - S0 = d (y1 + y0)/(S1 + S0), and asinh y1 - asinh y0 = d / r.
    let a = (y1 + y0) / (s1 + s0) * r;
    let h_mu_d = (z1 - z0) - (x1 - x0) * a;
    // h mu_d(Q0, Q1 + N s) = h mu_d(Q0, Q1) + s (1 + y1 A) = 0.
    let s = -h_mu_d / (point(1.0) + y1 * a);
    let xe = x1 - y1 * s;
    let ze = z1 + s;
    let xd0 = (xe - x0) * r / (s0 * hh);
    let yd0 = d / hh;
    let p_minus = vec![xd0 * (point(1.0) + y0.sqr()), yd0];
    let p_plus = vec![xd0 * s0 * s1, yd0];
    let l = hh * (xd0.sqr() * s0.sqr() + yd0.sqr()) * pt(0.5);
    ParticleRet {
        a,
        h_mu_d,
        s,
        q1: vec![xe, y1, ze],
        u0: vec![xd0, yd0],
        p_minus,
        p_plus,
        l,
    }
}

/// sin(a)/a over a box (1 at 0).
pub fn sinc(a: I) -> I {
    let at = |x: f64| -> I {
        if x < 1e-2 {
            // 1 - a^2/6 + a^4/120 - a^6/5040 + ...: alternating, decreasing terms.
            let t = point(x).sqr();
            let p = point(1.0) - t * q(1.0, 6.0) + t.sqr() * q(1.0, 120.0);
            p - up_to(t * t.sqr() * q(1.0, 5040.0))
        } else {
            point(x).sin() / point(x)
        }
    };
    if a.mag() < 1e-2 {
        // decreasing in |a| on [0, 1e-2]
        iv(at(a.mag()).inf(), at(a.mig()).sup())
    } else if a.mig() > 0.0 {
        a.sin() / a
    } else {
        // sinc >= -0.2173 everywhere
        iv(-0.25, 1.0)
    }
}

/// g(a) = (a - sin a)/a^3 over a box (1/6 at 0).
pub fn g3(a: I) -> I {
    let at = |x: f64| -> I {
        if x < 0.1 {
            // 1/6 - a^2/120 + a^4/5040 - a^6/362880 + a^8/39916800 - ...
            let t = point(x).sqr();
            let p = q(1.0, 6.0) - t * q(1.0, 120.0) + t.sqr() * q(1.0, 5040.0)
                - t * t.sqr() * q(1.0, 362880.0);
            p + up_to(t.sqr().sqr() * q(1.0, 39916800.0))
        } else {
            let a = point(x);
            (a - a.sin()) / (a * a.sqr())
        }
    };
    if a.mag() < 0.1 {
        // decreasing in |a| near 0
        iv(at(a.mag()).inf(), at(a.mig()).sup())
    } else if a.mig() > 0.0 {
        (a - a.sin()) / (a * a.sqr())
    } else {
        // 0 < (a - sin a)/a^3 <= 1/6 for every real a != 0
        iv(0.0, q(1.0, 6.0).sup())
    }
}

/// The knife's motion in closed form. With phi(t) = phi0 + D (D = phid0 t),
/// m = phi0 + D/2, c = sinc(D/2):
///   u1(t) = u10 + X1/2,          (u1' = cos(phi)/2)
///   x(t) = x0 + u10 X1 + X2,     X1 = t cos(m) c,  X2 = t^2 cos(m)^2 c^2 / 4,
///   y(t) = y0 + u10 Y1 + Y2,     Y1 = t sin(m) c,
///   Y2 = t^2 [ D g(2D) - sin^2(phi0) sin(D) c^2/4 + sin(phi0) cos(phi0) cos(D) c^2/4 ].
#[derive(Clone, Debug)]
pub struct KnifeParts {
    pub x1: I,
    pub y1: I,
    pub x2: I,
    pub y2: I,
    pub c: I,
}

pub fn knife_parts(phi0: I, dphi: I, t: I) -> KnifeParts {
    let half = dphi * pt(0.5);
    let m = phi0 + half;
    let c = sinc(half);
    let (cm, sm) = (m.cos(), m.sin());
    let (s0, c0) = (phi0.sin(), phi0.cos());
    let t2 = t.sqr();
    let c2q = c.sqr() * pt(0.25);
    KnifeParts {
        x1: t * cm * c,
        y1: t * sm * c,
        x2: t2 * cm.sqr() * c2q,
        y2: t2
            * (dphi * g3(dphi * pt(2.0)) - s0.sqr() * dphi.sin() * c2q
                + s0 * c0 * dphi.cos() * c2q),
        c,
    }
}

/// (q(t), u1(t)) of the knife from q0 with quasi-velocities u = (u10, phid0).
pub fn knife_q(q0: &[I], u: &[I], t: f64) -> (Vec<I>, I) {
    let tt = pt(t);
    let dphi = u[1] * tt;
    let k = knife_parts(q0[2], dphi, tt);
    (
        vec![
            q0[0] + u[0] * k.x1 + k.x2,
            q0[1] + u[0] * k.y1 + k.y2,
            q0[2] + dphi,
        ],
        u[0] + k.x1 * pt(0.5),
    )
}

/// Closed-form exact retraction of the knife at f64 inputs: q(h) = Q1 + N(Q1) s with
/// N(Q1) = (sin phi1, -cos phi1, 0); phi(h) = phi1 forces phid0 = (phi1 - phi0)/h, and the
/// two remaining equations are linear in (u10, s).
#[derive(Clone, Debug)]
pub struct KnifeRet {
    pub s: I,
    pub u0: Vec<I>,
    pub q1: Vec<I>,
    pub p_minus: Vec<I>,
    pub p_plus: Vec<I>,
}

pub fn knife_retraction(q0: &[f64], q1: &[f64], h: f64) -> KnifeRet {
    let (x0, y0, f0) = (pt(q0[0]), pt(q0[1]), pt(q0[2]));
    let (x1, y1, f1) = (pt(q1[0]), pt(q1[1]), pt(q1[2]));
    let hh = pt(h);
    let dphi = f1 - f0;
    let omega = dphi / hh;
    let k = knife_parts(f0, dphi, hh);
    let half = dphi * pt(0.5);
    let (s1, c1) = (f1.sin(), f1.cos());
    // X1 cos(phi1) + Y1 sin(phi1) = h c cos(D/2); X1 sin(phi1) - Y1 cos(phi1) = h c sin(D/2)
    let den = hh * k.c * half.cos();
    let u10 = ((x1 - x0 - k.x2) * c1 + (y1 - y0 - k.y2) * s1) / den;
    let s = (x0 + k.x2 - x1) * s1 - (y0 + k.y2 - y1) * c1 + u10 * hh * k.c * half.sin();
    KnifeRet {
        s,
        u0: vec![u10, omega],
        q1: vec![x1 + s1 * s, y1 - c1 * s, f1],
        p_minus: vec![u10, omega],
        p_plus: vec![u10 + k.x1 * pt(0.5), omega],
    }
}

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n, f64).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let kf = k as f64;
                let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        out.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    out
}
