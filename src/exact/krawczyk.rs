//! The Krawczyk operator with epsilon-inflation ([spec eq. (6.3)](crate::spec::exact_discrete), Theorem 6.1).

use crate::enclosure::linalg::{self, IMat};
use crate::enclosure::Ival;
use crate::Error;
use nalgebra::DMatrix;

/// A box containing the unique zero of `G` near `guess`, with `c` any float matrix
/// (best an approximate inverse of `DG(guess)`).
///
/// `gd(X)` must return an enclosure of `G(guess)` (for every parameter value) and one of
/// `DG` over the box `X` (one call: a flow of the box `X` gives both, [spec eq. (6.3)](crate::spec::exact_discrete)).
/// `rad` is the first radius tried: about twice the expected Newton correction.
/// `scale` is the magnitude the solution's rounding is measured against (the retraction
/// passes `max |u0|`): every component gets at least a few ulps of it.
///
/// # Containment
/// If `K(X) = z~ - C G(z~) + (I - C DG(X)) (X - z~)` lies in the interior of `X` (checked
/// componentwise in intervals), then `G` has exactly one zero in `X` and it lies in `K(X)`
/// (Krawczyk 1969; Moore 1977; [spec Theorem 6.1](crate::spec::exact_discrete)); `K(X)` is returned, narrowed by the
/// passes of [spec (6.3')](crate::spec::exact_discrete) (each keeps the zero). After 8 inflations without that inclusion:
/// `Error::Uncertified`.
pub fn krawczyk<I: Ival>(
    guess: &[I::Pt],
    c: &DMatrix<f64>,
    rad: &[f64],
    scale: f64,
    gd: impl Fn(&[I]) -> Result<(Vec<I>, Vec<Vec<I>>), Error>,
) -> Result<Vec<I>, Error> {
    // A floor of a few ulps of what reaches each component (not of the component itself: a
    // component that is exactly 0 needs room too, since the coupling through I - C DG moves
    // it by about eps times the other components). First the floor of what couples into
    // each component through the float C: with a pair far off M_h the defect s can be 1e16
    // while u0 is 1e5, and a floor of eps |s| on u0 made the box so wide that its flow took
    // thousands of steps and I - C DG never contracted (a rolling disk with R = 1e-8, or a
    // sleigh with m = 1e-300). Then, if that fails, also a few ulps of
    // `scale`: a component that nothing couples into in the float C still moves by the
    // width of the enclosure of DG (a particle pair with y1 = y0, u2 = s = 0, is certified
    // only so). Each try is a Krawczyk test on its own: which boxes are tried changes no
    // answer's soundness.
    let guess_f64: Vec<f64> = guess.iter().map(|x| I::pt_f64(*x)).collect();
    let coupled = coupled_floor(&guess_f64, c);
    let scaled: Vec<f64> = coupled
        .iter()
        .map(|f| f.max(2.0 * f64::EPSILON * scale.abs()))
        .collect();
    match inflate(guess, c, rad, &coupled, &gd) {
        Err(Failed::Other(_)) if scaled != coupled => {
            inflate(guess, c, rad, &scaled, &gd).map_err(Failed::into_error)
        }
        first => first.map_err(Failed::into_error),
    }
}

/// Why [`inflate`] gave up.
enum Failed {
    /// `I - C DG(X)` does not contract on the box: no larger box can pass (below).
    Hopeless(Error),
    Other(Error),
}

impl Failed {
    fn into_error(self) -> Error {
        match self {
            Failed::Hopeless(e) | Failed::Other(e) => e,
        }
    }
}

/// `min_i (|M| r)_i / r_i`, `|M|` the magnitudes of `M = I - C DG(X)` and `r` the box's
/// radii. It is a lower bound of the spectral radius of `|M|` (Collatz-Wielandt). The
/// inclusion `K(X) ⊂ int X` needs `(|M| r)_i < r_i` for every i, impossible once the
/// spectral radius is 1 or more; a larger box only widens `DG(X)` and so `|M|`. So when
/// this is above 1, inflating further is work without hope, and the test stops (a policy
/// that decides how soon to refuse; it changes no answer's soundness).
fn contraction_floor<I: Ival>(m: &IMat<I>, rad: &[f64]) -> f64 {
    (0..rad.len())
        .map(|i| {
            let mr: f64 = m[i].iter().zip(rad).map(|(x, r)| x.mag() * r).sum();
            mr / rad[i]
        })
        .fold(f64::INFINITY, f64::min)
}

/// Epsilon-inflation from the radii `rad` with the floor `floor`: at most 8 boxes.
fn inflate<I: Ival>(
    guess: &[I::Pt],
    c: &DMatrix<f64>,
    rad: &[f64],
    floor: &[f64],
    gd: &impl Fn(&[I]) -> Result<(Vec<I>, Vec<Vec<I>>), Error>,
) -> Result<Vec<I>, Failed> {
    let n = guess.len();
    let zt: Vec<I> = guess.iter().map(|x| I::pt(*x)).collect();
    let ci = linalg::imat(c);
    let mut rad: Vec<f64> = (0..n)
        .map(|i| rad[i].abs() + 8.0 * f64::EPSILON * I::pt_f64(guess[i]).abs() + floor[i])
        .collect();
    for _ in 0..8 {
        let x: Vec<I> = (0..n).map(|i| zt[i] + I::iv(-rad[i], rad[i])).collect();
        if !x.iter().all(|v| v.is_finite()) {
            break;
        }
        let (gz, d) = gd(&x).map_err(Failed::Other)?;
        let cg = linalg::mul_vec(&ci, &gz);
        if !cg.iter().all(|x| x.is_finite()) {
            return Err(Failed::Other(Error::uncertified(
                "shooting map not finite at the Newton point",
            )));
        }
        let i_minus_cd = linalg::identity_minus(&linalg::mul(&ci, &IMat::from_rows(&d)));
        let k = image(&zt, &cg, &i_minus_cd, &x);
        if k.iter()
            .zip(&x)
            .all(|(a, b)| a.is_finite() && a.interior(*b))
        {
            return refine(&zt, &cg, &i_minus_cd, k).map_err(Failed::Other);
        }
        let rho = contraction_floor(&i_minus_cd, &rad);
        if rho > 1.0 {
            return Err(Failed::Hopeless(Error::uncertified(format!(
                "Krawczyk test failed: I - C DG does not contract (spectral radius of its \
                 magnitudes >= {rho:.3e}; h too large or the Newton point too far)"
            ))));
        }
        // epsilon-inflation: grow the box towards K(X), and at least to twice the Newton
        // correction C G(z~), in the components where K(X) is not inside X. A component
        // that passed keeps its radius: growing it only widens DG(X), and with it what
        // the others must hold (a component that is 0 at the zero, coupled to one that
        // passed, chased that one's growth through every try).
        for i in 0..n {
            if k[i].is_finite() && k[i].interior(x[i]) {
                continue;
            }
            let reach = (k[i] - zt[i]).mag();
            rad[i] = (rad[i] * 2.0).max(reach * 2.0).max(2.0 * cg[i].mag()) + floor[i];
        }
    }
    Err(Failed::Other(Error::uncertified(
        "Krawczyk test failed: no existence and uniqueness proof (step too large, or a singular Jacobian)",
    )))
}

/// `z~ - C [G(z~)] + M (Y - z~)` ([spec (6.3)](crate::spec::exact_discrete)), `cg = C [G(z~)]` and `m = I - C [DG](X)`:
/// `K(X)` for `Y = X`, and each pass of (6.3').
fn image<I: Ival>(zt: &[I], cg: &[I], m: &IMat<I>, y: &[I]) -> Vec<I> {
    let dy: Vec<I> = y.iter().zip(zt).map(|(a, z)| *a - *z).collect();
    let lin = linalg::mul_vec(m, &dy);
    (0..y.len()).map(|i| zt[i] - cg[i] + lin[i]).collect()
}

/// Most passes of [`refine`] after a successful test.
const REFINE_PASSES: usize = 64;

/// (6.3') The zero `z*` that the test proved to lie in `K(X)` lies in
/// `z~ - C [G(z~)] + M (Y - z~)` for every box `Y ⊆ X` that contains it, with the same
/// enclosures `[G(z~)]` and `M = I - C [DG](X)` (mean value theorem on the segment from `z~`
/// to `z*`, which lies in the convex `X`). So `Y <- (z~ - C G(z~) + M (Y - z~)) ∩ Y` from
/// `Y = K(X)` keeps `z*` and costs no flow. Passes stop once no component narrows to below
/// 7/8 of its width, or after REFINE_PASSES. An empty intersection can only come from a
/// fault of the crate ([spec 0.4](crate::spec::overview#04-self-checks-vnode-lp-and-capd-style)).
fn refine<I: Ival>(zt: &[I], cg: &[I], m: &IMat<I>, mut y: Vec<I>) -> Result<Vec<I>, Error> {
    for _ in 0..REFINE_PASSES {
        let next: Vec<I> = image(zt, cg, m, &y)
            .iter()
            .zip(&y)
            .map(|(k, y)| k.intersection(*y))
            .collect();
        if next.iter().any(|x| x.is_empty()) {
            return Err(Error::internal_at(
                crate::Invariant::DisjointEnclosures,
                "self-check failed: a Krawczyk refinement lost the proved zero",
            ));
        }
        let settled = next.iter().zip(&y).all(|(a, b)| a.wid() >= 0.875 * b.wid());
        y = next;
        if settled {
            break;
        }
    }
    Ok(y)
}

/// (12.0.9) A box `y` known to hold the zero `z*` (proved by [`krawczyk`]), narrowed
/// around a new centre `zt` in `y`: with `[G(zt)]` = `g` and `[DG]` over `y` = `d`,
/// `z* ∈ zt - C [G(zt)] + (I - C [DG](y)) (y - zt)` for any matrix `C` (the mean value
/// theorem on the segment from `zt` to `z*`, inside the convex `y`), intersected with
/// `y`, then the passes of (6.3') with the same enclosures. `C` is the float inverse of
/// `mid([DG])`, else `c`.
pub fn recentred<I: Ival>(
    zt: &[I::Pt],
    c: &DMatrix<f64>,
    g: &[I],
    d: &[Vec<I>],
    y: Vec<I>,
) -> Result<Vec<I>, Error> {
    let zt: Vec<I> = zt.iter().map(|x| I::pt(*x)).collect();
    let n = zt.len();
    let c = DMatrix::from_fn(n, n, |i, j| d[i][j].mid())
        .try_inverse()
        .filter(|x| x.iter().all(|v| v.is_finite()))
        .unwrap_or_else(|| c.clone());
    let ci = linalg::imat(&c);
    let cg = linalg::mul_vec(&ci, g);
    let m = linalg::identity_minus(&linalg::mul(&ci, &IMat::from_rows(d)));
    refine(&zt, &cg, &m, y)
}

/// `2 eps (|C| |C^-1| |guess|)_i`: the room component i needs for the rounding of the
/// other components carried into it by `I - C DG` (`DG ~ C^-1`), per component.
fn coupled_floor(guess: &[f64], c: &DMatrix<f64>) -> Vec<f64> {
    let n = guess.len();
    let scale = guess.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let Some(j) = c.clone().try_inverse() else {
        return vec![2.0 * f64::EPSILON * scale + 1e-300; n];
    };
    let jg: Vec<f64> = (0..n)
        .map(|r| (0..n).map(|k| j[(r, k)].abs() * guess[k].abs()).sum())
        .collect();
    (0..n)
        .map(|i| {
            let f = (0..n).map(|r| c[(i, r)].abs() * jg[r]).sum::<f64>();
            2.0 * f64::EPSILON * f.min(scale * n as f64) + 1e-300
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::{iv, point};
    use inari::Interval;

    #[test]
    fn encloses_sqrt2_and_refuses_a_double_root() {
        // G(z) = z^2 - 2
        let r2 = point(std::f64::consts::SQRT_2);
        let gd = |z: &[Interval]| Ok((vec![r2 * r2 - point(2.0)], vec![vec![point(2.0) * z[0]]]));
        let c = DMatrix::from_element(1, 1, 1.0 / (2.0 * std::f64::consts::SQRT_2));
        let r = krawczyk(
            &[std::f64::consts::SQRT_2],
            &c,
            &[0.0],
            std::f64::consts::SQRT_2,
            gd,
        )
        .unwrap();
        assert!(r[0].contains(std::f64::consts::SQRT_2));
        assert!(r[0].wid() < 1e-15);
        assert!(r[0].interior(iv(1.0, 2.0)));
        // G(z) = z^2 has a double root at 0: no uniqueness proof possible
        let gd = |z: &[Interval]| {
            Ok((
                vec![point(1e-9) * point(1e-9)],
                vec![vec![point(2.0) * z[0]]],
            ))
        };
        let c = DMatrix::from_element(1, 1, 1.0 / 2e-9);
        assert!(krawczyk(&[1e-9], &c, &[0.0], 1e-9, gd).is_err());
    }

    #[test]
    fn refinement_narrows_k_of_x_and_keeps_the_zero() {
        // G(z) = z^2 - 2 from the poor guess z~ = 1.5, C = 1/3, X = 1.5 + [-0.2, 0.2]:
        // DG(X) = 2 X = [2.6, 3.4], M = 1 - C DG(X) = [-2/15, 2/15], C G(z~) = 1/12, so
        // K(X) = 17/12 + M [-0.2, 0.2], 2 (2/15) 0.2 = 0.0533 wide, inside X. One pass of
        // (6.3') from Y = K(X) (Y - z~ within [-0.11, -0.057]) gives at most
        // 17/12 +- (2/15) 0.11, 0.0294 wide.
        let gd = |z: &[Interval]| {
            let g = point(1.5) * point(1.5) - point(2.0);
            Ok((vec![g], vec![vec![point(2.0) * z[0]]]))
        };
        let c = DMatrix::from_element(1, 1, 1.0 / 3.0);
        let r = krawczyk(&[1.5], &c, &[0.2], 1.5, gd).unwrap();
        assert!(r[0].contains(std::f64::consts::SQRT_2));
        assert!(r[0].wid() < 0.0295, "not refined: {:?}", r[0]);
        assert!(r[0].subset(iv(17.0 / 12.0 - 0.027, 17.0 / 12.0 + 0.027)));
    }

    /// (12.0.9): narrowed around a new centre, a box proved to hold the zero keeps it and
    /// comes down to the rounding level, whatever the `c` passed (the float inverse of
    /// `mid([DG])` is used): `G(z) = z^2 - 2` over `y = sqrt 2 + [-1e-10, 2e-10]`, centre its
    /// midpoint (`M (y - zt)` is then about `1e-10 * 1e-10`).
    #[test]
    fn a_recentred_box_keeps_the_zero_and_narrows_to_the_rounding_level() {
        let r2 = std::f64::consts::SQRT_2;
        let y = vec![iv(r2 - 1e-10, r2 + 2e-10)];
        let zt = [y[0].mid()];
        let g = vec![point(zt[0]) * point(zt[0]) - point(2.0)];
        let d = vec![vec![point(2.0) * y[0]]];
        let c = DMatrix::from_element(1, 1, 100.0);
        let r = recentred(&zt, &c, &g, &d, y).unwrap();
        assert!(r[0].contains(r2), "{:?}", r[0]);
        assert!(r[0].wid() < 4.0 * f64::EPSILON, "not narrowed: {:?}", r[0]);
    }
}
