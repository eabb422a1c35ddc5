//! The evaluator (an [`Expr`] over any [`Scalar`], by the number and exponent rules) and the
//! canonical printer (fully parenthesised text that parses back to the same tree).

use super::{Exponent, Expr, Names};
use crate::scalar::Scalar;

/// `b ^ n` by squaring (n >= 0).
fn powi<S: Scalar>(b: S, n: u32) -> S {
    if n == 0 {
        return S::one();
    }
    let mut acc: Option<S> = None;
    let mut sq = b;
    let mut m = n;
    loop {
        if m & 1 == 1 {
            acc = Some(match acc {
                None => sq.clone(),
                Some(a) => a * sq.clone(),
            });
        }
        m >>= 1;
        if m == 0 {
            break;
        }
        sq = sq.sqr();
    }
    acc.unwrap_or_else(S::one)
}

impl Expr {
    /// The value at `q` with parameter values `params` (each an exact constant, or a name
    /// for the symbolic rendering).
    pub fn eval<S: Scalar>(&self, q: &[S], params: &[S]) -> S {
        match self {
            Expr::Num(v) => S::cst(*v),
            Expr::Pi => S::pi(),
            Expr::Coord(i) => q.get(*i).cloned().unwrap_or_else(S::zero),
            Expr::Param(i) => params.get(*i).cloned().unwrap_or_else(S::zero),
            Expr::Neg(e) => -e.eval(q, params),
            Expr::Sum(first, rest) => rest.iter().fold(first.eval(q, params), |acc, (minus, e)| {
                if *minus {
                    acc - e.eval(q, params)
                } else {
                    acc + e.eval(q, params)
                }
            }),
            Expr::Product(first, rest) => {
                rest.iter().fold(first.eval(q, params), |acc, (div, e)| {
                    if *div {
                        acc / e.eval(q, params)
                    } else {
                        acc * e.eval(q, params)
                    }
                })
            }
            Expr::Pow(b, ex) => {
                let b = b.eval(q, params);
                match ex {
                    Exponent::Int(n) if *n >= 0 => powi(b, n.unsigned_abs()),
                    Exponent::Int(n) => S::one() / powi(b, n.unsigned_abs()),
                    Exponent::Half(false) => b.sqrt(),
                    Exponent::Half(true) => S::one() / b.sqrt(),
                    Exponent::General(e) => (e.eval(q, params) * b.ln()).exp(),
                }
            }
            Expr::Call(f, e) => f.apply(e.eval(q, params)),
        }
    }

    /// A canonical text: fully parenthesised, numbers in their shortest round-trip form,
    /// names as given. Parsing it with the same names gives the same tree.
    pub fn canonical(&self, names: &Names) -> String {
        let mut s = String::new();
        self.write(names, &mut s);
        s
    }

    /// The nesting depth (as the reader counts it: parentheses, calls, powers and unary
    /// minus) of [`Expr::canonical`]'s text, computed from the tree as `write` writes it.
    pub(super) fn canonical_depth(&self) -> usize {
        match self {
            // a literal is non-negative; a sign would be a unary minus
            Expr::Num(v) => usize::from(v.is_sign_negative()),
            Expr::Pi | Expr::Coord(_) | Expr::Param(_) => 0,
            // `(-e)`
            Expr::Neg(e) => 2 + e.canonical_depth(),
            // `(a + b - ...)`
            Expr::Sum(first, rest) | Expr::Product(first, rest) => {
                1 + rest
                    .iter()
                    .map(|(_, e)| e.canonical_depth())
                    .fold(first.canonical_depth(), usize::max)
            }
            // `(b^n)`, `(b^-n)`, `(b^(e))`: the exponent is read after `^`, one level in
            Expr::Pow(b, ex) => {
                let exponent = match ex {
                    Exponent::Int(n) => usize::from(*n < 0),
                    Exponent::Half(minus) => usize::from(*minus),
                    Exponent::General(e) => 1 + e.canonical_depth(),
                };
                1 + b.canonical_depth().max(1 + exponent)
            }
            // `f(e)`
            Expr::Call(_, e) => 1 + e.canonical_depth(),
        }
    }

    fn write(&self, names: &Names, s: &mut String) {
        match self {
            Expr::Num(v) => s.push_str(&format!("{v:?}")),
            Expr::Pi => s.push_str("pi"),
            Expr::Coord(i) => s.push_str(names.coordinates.get(*i).map_or("?", |x| x)),
            Expr::Param(i) => s.push_str(names.parameters.get(*i).map_or("?", |x| x)),
            Expr::Neg(e) => {
                s.push_str("(-");
                e.write(names, s);
                s.push(')');
            }
            Expr::Sum(first, rest) | Expr::Product(first, rest) => {
                let ops = if matches!(self, Expr::Sum(..)) {
                    ['+', '-']
                } else {
                    ['*', '/']
                };
                s.push('(');
                first.write(names, s);
                for (inv, e) in rest {
                    s.push(ops[*inv as usize]);
                    e.write(names, s);
                }
                s.push(')');
            }
            Expr::Pow(b, ex) => {
                s.push('(');
                b.write(names, s);
                s.push('^');
                match ex {
                    Exponent::Int(n) => s.push_str(&n.to_string()),
                    Exponent::Half(false) => s.push_str("0.5"),
                    Exponent::Half(true) => s.push_str("-0.5"),
                    Exponent::General(e) => {
                        s.push('(');
                        e.write(names, s);
                        s.push(')');
                    }
                }
                s.push(')');
            }
            Expr::Call(f, e) => {
                s.push_str(f.name());
                s.push('(');
                e.write(names, s);
                s.push(')');
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_names::{ev, names, p};
    use super::super::{parse, Names, MAX_DEPTH};

    #[test]
    fn precedence_and_associativity() {
        let q = [3.0, 5.0, 0.0];
        assert_eq!(ev("1 + 2*3", &q), 7.0);
        assert_eq!(ev("x - y - 1", &q), -3.0);
        assert_eq!(ev("x / y * 5", &q), 3.0);
        assert_eq!(ev("-x^2", &q), -9.0);
        assert_eq!(ev("2^3^2", &q), 512.0f64.ln().exp()); // 2^(3^2), real exponent path
        assert_eq!(ev("2^-3", &q), 0.125);
        assert_eq!(ev("x^0", &q), 1.0);
        assert_eq!(ev("(x+y)*m", &q), 16.0);
        assert_eq!(ev("4^0.5", &q), 2.0);
        assert_eq!(ev("4^-0.5", &q), 0.5);
        assert_eq!(ev("1e2 + .5 + 2.", &q), 102.5);
        assert_eq!(ev("ln(1) + log(1)", &q), 0.0);
    }

    #[test]
    fn intervals_enclose_the_reals() {
        let q = [crate::scalar::point(1.0); 3];
        let pars = [crate::scalar::point(1.0); 2];
        let v = p("(1/3)*3").unwrap().eval(&q, &pars);
        assert!(v.contains(1.0) && v.inf() < v.sup());
        let pi = p("pi").unwrap().eval(&q, &pars);
        assert!(pi.contains(std::f64::consts::PI) && pi.inf() < pi.sup());
        let third = p("1/3").unwrap().eval(&q, &pars);
        assert!(third.inf() < 1.0 / 3.0 || third.sup() > 1.0 / 3.0);
    }

    #[test]
    fn canonical_text_parses_back_to_the_same_tree() {
        let (c, pa) = names();
        let nm = Names {
            coordinates: &c,
            parameters: &pa,
        };
        for src in [
            "-x^2 + m*g*y - 1/3",
            "x^(y) * 2^-3 * phi^-0.5 * 1e-7 * 0.1",
            "sin(phi)/cos(phi) - tan(phi) + (x - (y - 1))",
            "x^(-1.5) + x^--2 + exp(ln(sqrt(2)))",
        ] {
            let e = parse(src, &nm).unwrap();
            let c1 = e.canonical(&nm);
            assert_eq!(parse(&c1, &nm).unwrap(), e, "{src} -> {c1}");
        }
        // Chains that nest shallowly as written but deeply once parenthesised (the
        // `scene_file` fuzz target's finding: `-0.25^-1^-1^...`, 2 levels a power as written
        // and 4 in canonical form) are refused from the first length whose canonical form
        // would pass the limit, and read back below it.
        let chains: [fn(usize) -> String; 5] = [
            |k| format!("-0.25{}", "^-1".repeat(k)),
            |k| format!("x{}", "^(y)".repeat(k)),
            |k| format!("{}x", "-".repeat(k)),
            |k| format!("{}x{}", "sin(2*".repeat(k), ")".repeat(k)),
            |k| format!("{}x{}", "(y+".repeat(k), ")^0.5".repeat(k)),
        ];
        for (i, chain) in chains.iter().enumerate() {
            let mut accepted = 0;
            for k in 1..=120 {
                match parse(&chain(k), &nm) {
                    Ok(e) => {
                        accepted = k;
                        let text = e.canonical(&nm);
                        let again = parse(&text, &nm)
                            .unwrap_or_else(|err| panic!("chain {i}, {k}: {text}: {err:?}"));
                        assert_eq!(again.canonical(&nm), text, "chain {i}, {k}");
                        assert!(e.canonical_depth() <= MAX_DEPTH);
                    }
                    Err(err) => assert!(err.what.contains("nested more than"), "{err:?}"),
                }
            }
            // some lengths were read, and the longest ones refused
            assert!((10..120).contains(&accepted), "chain {i}: {accepted}");
        }
    }
}
