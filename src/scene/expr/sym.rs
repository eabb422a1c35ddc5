//! The symbolic scalar: formulas written as text, for the descriptions of derived bases.

use crate::scalar::Scalar;

/// A formula as a string, for the descriptions of derived bases: a [`Scalar`] whose
/// operations build text, with the simplifications 0 + a = a, 1 * a = a, 0 * a = 0,
/// a / 1 = a and -(-a) = a (exact for every value where the formula is defined).
#[derive(Clone, Debug, PartialEq)]
pub struct Sym {
    text: String,
    /// 0: a sum, 1: a product or quotient, 2: a negation, 3: a power, 4: an atom or a call.
    prec: u8,
    /// For a negation, the precedence of its operand (0: written in parentheses).
    inner: u8,
}

impl Sym {
    pub fn name(s: &str) -> Sym {
        Sym {
            text: s.to_string(),
            prec: 4,
            inner: 4,
        }
    }
    pub fn text(&self) -> &str {
        &self.text
    }
    fn is(&self, s: &str) -> bool {
        self.text == s
    }
    fn at_least(&self, p: u8) -> String {
        if self.prec >= p {
            self.text.clone()
        } else {
            format!("({})", self.text)
        }
    }
    fn strip_neg(&self) -> Option<Sym> {
        if self.prec != 2 {
            return None;
        }
        let text = if self.inner == 0 {
            self.text.get(2..self.text.len().saturating_sub(1))?
        } else {
            self.text.get(1..)?
        };
        Some(Sym {
            text: text.to_string(),
            prec: self.inner,
            inner: self.inner,
        })
    }
    fn call(&self, f: &str) -> Sym {
        Sym {
            text: format!("{f}({})", self.text),
            prec: 4,
            inner: 4,
        }
    }
}

impl std::ops::Add for Sym {
    type Output = Sym;
    fn add(self, o: Sym) -> Sym {
        if self.is("0") {
            return o;
        }
        if o.is("0") {
            return self;
        }
        if let Some(p) = o.strip_neg() {
            return self - p;
        }
        Sym {
            text: format!("{} + {}", self.text, o.at_least(1)),
            prec: 0,
            inner: 4,
        }
    }
}

impl std::ops::Sub for Sym {
    type Output = Sym;
    fn sub(self, o: Sym) -> Sym {
        if o.is("0") {
            return self;
        }
        if self.is("0") {
            return -o;
        }
        if let Some(p) = o.strip_neg() {
            return self + p;
        }
        Sym {
            text: format!("{} - {}", self.text, o.at_least(1)),
            prec: 0,
            inner: 4,
        }
    }
}

impl std::ops::Mul for Sym {
    type Output = Sym;
    fn mul(self, o: Sym) -> Sym {
        if self.is("0") || o.is("0") {
            return Sym::cst_text("0");
        }
        if self.is("1") {
            return o;
        }
        if o.is("1") {
            return self;
        }
        if let Some(p) = self.strip_neg() {
            return -(p * o);
        }
        if let Some(p) = o.strip_neg() {
            return -(self * p);
        }
        Sym {
            text: format!("{}*{}", self.at_least(1), o.at_least(2)),
            prec: 1,
            inner: 4,
        }
    }
}

impl std::ops::Div for Sym {
    type Output = Sym;
    fn div(self, o: Sym) -> Sym {
        if o.is("1") {
            return self;
        }
        if self.is("0") {
            return Sym::cst_text("0");
        }
        if let Some(p) = self.strip_neg() {
            return -(p / o);
        }
        if let Some(p) = o.strip_neg() {
            return -(self / p);
        }
        Sym {
            text: format!("{}/{}", self.at_least(1), o.at_least(3)),
            prec: 1,
            inner: 4,
        }
    }
}

impl std::ops::Neg for Sym {
    type Output = Sym;
    fn neg(self) -> Sym {
        if self.is("0") {
            return self;
        }
        if let Some(p) = self.strip_neg() {
            return p;
        }
        // -a*b reads as -(a*b) (the same number), so only a sum needs parentheses
        Sym {
            text: format!("-{}", self.at_least(1)),
            prec: 2,
            inner: self.prec,
        }
    }
}

impl Sym {
    fn cst_text(s: &str) -> Sym {
        Sym::name(s)
    }
}

impl Scalar for Sym {
    fn cst(c: f64) -> Self {
        let t = if c == c.trunc() && c.abs() < 1e15 {
            format!("{}", c.abs() as i64)
        } else {
            format!("{:?}", c.abs())
        };
        let s = Sym::name(&t);
        if c.is_sign_negative() && c != 0.0 {
            -s
        } else {
            s
        }
    }
    fn sin(&self) -> Self {
        self.call("sin")
    }
    fn cos(&self) -> Self {
        self.call("cos")
    }
    fn sqrt(&self) -> Self {
        self.call("sqrt")
    }
    fn exp(&self) -> Self {
        self.call("exp")
    }
    fn ln(&self) -> Self {
        self.call("log")
    }
    fn atan(&self) -> Self {
        self.call("atan")
    }
    fn sinh(&self) -> Self {
        self.call("sinh")
    }
    fn cosh(&self) -> Self {
        self.call("cosh")
    }
    fn tan(&self) -> Self {
        self.call("tan")
    }
    fn tanh(&self) -> Self {
        self.call("tanh")
    }
    fn pi() -> Self {
        Sym::name("pi")
    }
    fn sqr(&self) -> Self {
        Sym {
            text: format!("{}^2", self.at_least(4)),
            prec: 3,
            inner: 4,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{parse, Names};
    use super::Sym;
    use crate::scalar::Scalar;

    #[test]
    fn symbols_simplify_zeros_ones_and_double_negations() {
        let a = Sym::name("a");
        let b = Sym::name("b");
        assert_eq!((Sym::zero() + a.clone() * Sym::one()).text(), "a");
        assert_eq!((-(a.clone() / -b.clone())).text(), "a/b");
        assert_eq!((a.clone() - -b.clone()).text(), "a + b");
        assert_eq!((a.clone() * (b.clone() + a.clone())).text(), "a*(b + a)");
        assert_eq!((-(a.clone() + b.clone())).text(), "-(a + b)");
        assert_eq!((-(a.clone() * b.clone()) - a.clone()).text(), "-a*b - a");
        assert_eq!((-(a.clone() * b.clone())).sqr().text(), "(-a*b)^2");
        assert_eq!((-(-(a.clone() * b.clone()))).text(), "a*b");
        assert_eq!((a.clone() / -(a.clone() + b.clone())).text(), "-a/(a + b)");
        assert_eq!((-(-(a.clone() + b.clone()))).text(), "a + b");
        assert_eq!(Sym::cst(-0.5).text(), "-0.5");
    }

    /// The formulas the symbolic scalar writes mean what was computed: random computations
    /// done over [`Sym`] and over f64 side by side, the text parsed and evaluated again,
    /// give the same f64 (the simplifications and the parentheses change no rounding).
    #[test]
    fn symbolic_formulas_evaluate_to_what_was_computed() {
        let names: Vec<String> = vec!["a".into(), "b".into(), "c".into()];
        let vals = [0.7, -1.3, 2.25];
        let nm = Names {
            coordinates: &names,
            parameters: &[],
        };
        let mut seed = 0x5EEDu64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as usize
        };
        for _ in 0..2000 {
            let mut pool: Vec<(Sym, f64)> = (0..3)
                .map(|i| (Sym::name(&names[i]), vals[i]))
                .chain([
                    (Sym::zero(), 0.0),
                    (Sym::one(), 1.0),
                    (Sym::cst(-0.5), -0.5),
                ])
                .collect();
            for _ in 0..8 {
                let (x, fx) = pool[next() % pool.len()].clone();
                let (y, fy) = pool[next() % pool.len()].clone();
                let r = match next() % 7 {
                    0 => (x + y, fx + fy),
                    1 => (x - y, fx - fy),
                    2 => (x * y, fx * fy),
                    3 if fy != 0.0 => (x / y, fx / fy),
                    4 => (-x, -fx),
                    5 => (x.sqr(), fx * fx),
                    _ => (x.sin(), fx.sin()),
                };
                pool.push(r);
            }
            let (sym, want) = pool.last().unwrap().clone();
            let got = parse(sym.text(), &nm)
                .unwrap_or_else(|e| panic!("{}: {e:?}", sym.text()))
                .eval(&vals, &[]);
            assert!(
                got == want || (got - want).abs() <= 1e-15 * want.abs(),
                "{} = {got}, computed {want}",
                sym.text()
            );
        }
    }
}
