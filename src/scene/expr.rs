//! Expressions of scene files (spec/10-scene-files.md, "Expressions"): parsed once into a
//! small tree whose names are resolved to coordinate and parameter indices, then evaluated
//! over any `S: Scalar` by walking the tree (so a scene file records on the same tapes as a
//! built-in scene).
//!
//! The number rule: a decimal literal is the nearest f64 (Rust's correctly rounded parse)
//! and enters through [`Scalar::cst`], exactly; `pi` is [`Scalar::pi`]; nothing is folded
//! (`1/3` is the real quotient of two exact constants, evaluated in `S`).
//!
//! The exponent rule: `b ^ n` with a literal integer `n` (|n| <= [`MAX_INT_EXPONENT`]) is
//! repeated multiplication (by squaring; a negative `n` gives the reciprocal), `b ^ 0.5` is
//! `sqrt(b)` and `b ^ -0.5` is `1 / sqrt(b)`; any other exponent `e` is `exp(e * log(b))`,
//! defined for `b > 0` only.

use crate::scalar::Scalar;

/// The largest magnitude of a literal integer exponent.
pub const MAX_INT_EXPONENT: i32 = 1024;
/// The deepest nesting (parentheses, function calls, powers, unary minus) an expression
/// may have, as written and as its canonical form writes it (every sum, product, negation
/// and power in parentheses): evaluation walks the tree recursively.
pub const MAX_DEPTH: usize = 100;
/// The longest expression, in characters.
pub const MAX_LEN: usize = 100_000;

/// The analytic functions of the grammar, in the order the messages list them.
pub const FUNCTIONS: &[&str] = &[
    "sin", "cos", "tan", "exp", "log", "ln", "sqrt", "atan", "sinh", "cosh", "tanh",
];

/// Names of common non-analytic functions: refused with that reason (the validated flow
/// needs data analytic where they are evaluated).
pub const NOT_ANALYTIC: &[&str] = &[
    "abs",
    "min",
    "max",
    "floor",
    "ceil",
    "sign",
    "sgn",
    "signum",
    "round",
    "mod",
    "fmod",
    "rem",
    "trunc",
    "fract",
    "frac",
    "heaviside",
    "step",
    "clamp",
];

/// An analytic function of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Exp,
    Ln,
    Sqrt,
    Atan,
    Sinh,
    Cosh,
    Tanh,
}

impl Func {
    fn from_name(s: &str) -> Option<Func> {
        Some(match s {
            "sin" => Func::Sin,
            "cos" => Func::Cos,
            "tan" => Func::Tan,
            "exp" => Func::Exp,
            "log" | "ln" => Func::Ln,
            "sqrt" => Func::Sqrt,
            "atan" => Func::Atan,
            "sinh" => Func::Sinh,
            "cosh" => Func::Cosh,
            "tanh" => Func::Tanh,
            _ => return None,
        })
    }
    fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Exp => "exp",
            Func::Ln => "log",
            Func::Sqrt => "sqrt",
            Func::Atan => "atan",
            Func::Sinh => "sinh",
            Func::Cosh => "cosh",
            Func::Tanh => "tanh",
        }
    }
    fn apply<S: Scalar>(self, x: S) -> S {
        match self {
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Exp => x.exp(),
            Func::Ln => x.ln(),
            Func::Sqrt => x.sqrt(),
            Func::Atan => x.atan(),
            Func::Sinh => x.sinh(),
            Func::Cosh => x.cosh(),
            Func::Tanh => x.tanh(),
        }
    }
}

/// The exponent of a power, classified by the exponent rule.
#[derive(Clone, Debug, PartialEq)]
pub enum Exponent {
    /// A literal integer: repeated multiplication.
    Int(i32),
    /// A literal 0.5 (`true`: -0.5): the square root (or its reciprocal).
    Half(bool),
    /// Anything else: `exp(e * log(b))`.
    General(Box<Expr>),
}

/// A parsed expression with its names resolved.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A finite, non-negative f64 (a literal; a sign is a [`Expr::Neg`]).
    Num(f64),
    Pi,
    /// Coordinate q[i].
    Coord(usize),
    /// Parameter number i.
    Param(usize),
    Neg(Box<Expr>),
    /// `first (+|-) rest ...`, evaluated left to right; `true` marks a minus.
    Sum(Box<Expr>, Vec<(bool, Expr)>),
    /// `first (*|/) rest ...`, evaluated left to right; `true` marks a division.
    Product(Box<Expr>, Vec<(bool, Expr)>),
    Pow(Box<Expr>, Exponent),
    Call(Func, Box<Expr>),
}

/// Why an expression was refused: the message (without the place) and, where it has one,
/// the 1-based character position.
#[derive(Clone, Debug, PartialEq)]
pub struct ExprError {
    pub what: String,
    pub at: Option<usize>,
}

/// The names an expression may use.
pub struct Names<'a> {
    pub coordinates: &'a [String],
    pub parameters: &'a [String],
}

impl Names<'_> {
    /// "coordinates x, y; parameters m; pi": what an unknown name could have been.
    pub fn known(&self) -> String {
        let mut s = format!("coordinates {}", self.coordinates.join(", "));
        if !self.parameters.is_empty() {
            s.push_str(&format!("; parameters {}", self.parameters.join(", ")));
        }
        s.push_str("; the constant pi");
        s
    }
}

/// Whether `s` is an identifier: `[A-Za-z_][A-Za-z0-9_]*`.
pub fn is_identifier(s: &str) -> bool {
    let mut c = s.chars();
    matches!(c.next(), Some(f) if f.is_ascii_alphabetic() || f == '_')
        && c.all(|x| x.is_ascii_alphanumeric() || x == '_')
}

/// Whether `s` is reserved by the grammar (a function, a refused function or `pi`).
pub fn is_reserved(s: &str) -> bool {
    s == "pi" || FUNCTIONS.contains(&s) || NOT_ANALYTIC.contains(&s)
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64, String),
    Name(String),
    Op(char),
}

/// `s` with control characters shown as spaces (so a message stays on one line and the
/// character positions still count), cut to `max` characters.
pub fn shown(s: &str, max: usize) -> String {
    let mut out: String = s
        .chars()
        .take(max)
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    if s.chars().nth(max).is_some() {
        out.push_str("...");
    }
    out
}

fn tokenize(src: &str) -> Result<Vec<(Tok, usize)>, ExprError> {
    let chars: Vec<char> = src.chars().collect();
    let mut toks = Vec::new();
    let mut i = 0;
    let err = |what: String, at: usize| ExprError { what, at: Some(at) };
    while i < chars.len() {
        let c = chars[i];
        let at = i + 1;
        if c == ' ' || c == '\t' || c == '\n' || c == '\r' {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            while i < chars.len() && chars[i].is_ascii_digit() {
                i += 1;
            }
            if i < chars.len() && chars[i] == '.' {
                i += 1;
                while i < chars.len() && chars[i].is_ascii_digit() {
                    i += 1;
                }
            }
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    while j < chars.len() && chars[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                }
            }
            let text: String = chars[start..i].iter().collect();
            // Rust's parse of a decimal literal is correctly rounded (the nearest f64).
            let v: f64 = text
                .parse()
                .map_err(|_| err(format!("malformed number `{text}`"), at))?;
            if !v.is_finite() {
                return Err(err(
                    format!("the number `{}` is not finite as an f64", shown(&text, 40)),
                    at,
                ));
            }
            toks.push((Tok::Num(v, text), at));
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            toks.push((Tok::Name(chars[start..i].iter().collect()), at));
        } else if "+-*/^(),".contains(c) {
            toks.push((Tok::Op(c), at));
            i += 1;
        } else {
            let what = if c.is_control() {
                format!("unexpected control character U+{:04X}", c as u32)
            } else {
                format!("unexpected character `{c}`")
            };
            return Err(err(what, at));
        }
    }
    Ok(toks)
}

struct Parser<'a> {
    toks: Vec<(Tok, usize)>,
    pos: usize,
    end: usize,
    names: &'a Names<'a>,
    depth: usize,
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Num(_, s) => format!("number `{}`", shown(s, 40)),
        Tok::Name(s) => format!("name `{}`", shown(s, 40)),
        Tok::Op(c) => format!("`{c}`"),
    }
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos).map(|t| &t.0)
    }
    fn at(&self) -> usize {
        self.toks.get(self.pos).map(|t| t.1).unwrap_or(self.end)
    }
    fn unexpected(&self) -> ExprError {
        match self.toks.get(self.pos) {
            Some((t, at)) => ExprError {
                what: format!("unexpected {}", describe(t)),
                at: Some(*at),
            },
            None => ExprError {
                what: "unexpected end of the expression".into(),
                at: Some(self.end),
            },
        }
    }
    fn enter(&mut self) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(ExprError {
                what: format!("nested more than {MAX_DEPTH} deep"),
                at: Some(self.at()),
            });
        }
        Ok(())
    }
    fn eat(&mut self, c: char) -> bool {
        if self.peek() == Some(&Tok::Op(c)) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn expr(&mut self) -> Result<Expr, ExprError> {
        let first = self.term()?;
        let mut rest = Vec::new();
        loop {
            let minus = match self.peek() {
                Some(Tok::Op('+')) => false,
                Some(Tok::Op('-')) => true,
                _ => break,
            };
            self.pos += 1;
            rest.push((minus, self.term()?));
        }
        Ok(if rest.is_empty() {
            first
        } else {
            Expr::Sum(Box::new(first), rest)
        })
    }

    fn term(&mut self) -> Result<Expr, ExprError> {
        let first = self.unary()?;
        let mut rest = Vec::new();
        loop {
            let div = match self.peek() {
                Some(Tok::Op('*')) => false,
                Some(Tok::Op('/')) => true,
                _ => break,
            };
            self.pos += 1;
            rest.push((div, self.unary()?));
        }
        Ok(if rest.is_empty() {
            first
        } else {
            Expr::Product(Box::new(first), rest)
        })
    }

    fn unary(&mut self) -> Result<Expr, ExprError> {
        if self.eat('-') {
            self.enter()?;
            let e = self.unary()?;
            self.depth -= 1;
            return Ok(Expr::Neg(Box::new(e)));
        }
        self.power()
    }

    fn power(&mut self) -> Result<Expr, ExprError> {
        let base = self.primary()?;
        if !self.eat('^') {
            return Ok(base);
        }
        let at = self.at();
        self.enter()?;
        let e = self.unary()?;
        self.depth -= 1;
        let literal = match &e {
            Expr::Num(v) => Some(*v),
            Expr::Neg(inner) => match **inner {
                Expr::Num(v) => Some(-v),
                _ => None,
            },
            _ => None,
        };
        let exponent = match literal {
            Some(v) if v == v.trunc() => {
                if v.abs() > MAX_INT_EXPONENT as f64 {
                    return Err(ExprError {
                        what: format!(
                            "the integer exponent {v} is beyond {MAX_INT_EXPONENT} in magnitude \
                             (write exp(n*log(b)) for b > 0)"
                        ),
                        at: Some(at),
                    });
                }
                Exponent::Int(v as i32)
            }
            Some(v) if v.abs() == 0.5 => Exponent::Half(v < 0.0),
            _ => Exponent::General(Box::new(e)),
        };
        Ok(Expr::Pow(Box::new(base), exponent))
    }

    fn primary(&mut self) -> Result<Expr, ExprError> {
        let Some((tok, at)) = self.toks.get(self.pos).cloned() else {
            return Err(self.unexpected());
        };
        match tok {
            Tok::Num(v, _) => {
                self.pos += 1;
                Ok(Expr::Num(v))
            }
            Tok::Op('(') => {
                self.pos += 1;
                self.enter()?;
                let e = self.expr()?;
                self.depth -= 1;
                if !self.eat(')') {
                    return Err(self.unexpected_or_unclosed(at));
                }
                Ok(e)
            }
            Tok::Op(_) => Err(self.unexpected()),
            Tok::Name(name) => {
                self.pos += 1;
                let call = self.peek() == Some(&Tok::Op('('));
                if let Some(f) = Func::from_name(&name) {
                    if !call {
                        return Err(ExprError {
                            what: format!(
                                "the function `{name}` needs its argument in parentheses"
                            ),
                            at: Some(at),
                        });
                    }
                    self.pos += 1;
                    self.enter()?;
                    let arg = self.expr()?;
                    self.depth -= 1;
                    if !self.eat(')') {
                        if self.peek() == Some(&Tok::Op(',')) {
                            return Err(ExprError {
                                what: format!("the function `{name}` takes one argument"),
                                at: Some(self.at()),
                            });
                        }
                        return Err(self.unexpected_or_unclosed(at));
                    }
                    return Ok(Expr::Call(f, Box::new(arg)));
                }
                if NOT_ANALYTIC.contains(&name.as_str()) {
                    return Err(ExprError {
                        what: format!(
                            "the function `{name}` is refused: not analytic (the validated flow \
                             needs data analytic where they are evaluated)"
                        ),
                        at: Some(at),
                    });
                }
                if name == "pi" {
                    if call {
                        return Err(self.unexpected());
                    }
                    return Ok(Expr::Pi);
                }
                let resolved =
                    if let Some(i) = self.names.coordinates.iter().position(|c| *c == name) {
                        Some(Expr::Coord(i))
                    } else {
                        self.names
                            .parameters
                            .iter()
                            .position(|c| *c == name)
                            .map(Expr::Param)
                    };
                match resolved {
                    Some(_) if call => Err(ExprError {
                        what: format!("`{name}` is not a function"),
                        at: Some(at),
                    }),
                    Some(e) => Ok(e),
                    None if call => Err(ExprError {
                        what: format!(
                            "unknown function `{}` (known: {})",
                            shown(&name, 40),
                            FUNCTIONS.join(", ")
                        ),
                        at: Some(at),
                    }),
                    None => Err(ExprError {
                        what: format!(
                            "unknown name `{}` (known: {})",
                            shown(&name, 40),
                            self.names.known()
                        ),
                        at: Some(at),
                    }),
                }
            }
        }
    }

    fn unexpected_or_unclosed(&self, open: usize) -> ExprError {
        if self.pos >= self.toks.len() {
            ExprError {
                what: format!("the `(` at character {open} is not closed"),
                at: None,
            }
        } else {
            self.unexpected()
        }
    }
}

/// Parse `src` with the names `names`.
pub fn parse(src: &str, names: &Names) -> Result<Expr, ExprError> {
    let n = src.chars().count();
    if n > MAX_LEN {
        return Err(ExprError {
            what: format!("the expression has {n} characters (at most {MAX_LEN})"),
            at: None,
        });
    }
    let toks = tokenize(src)?;
    if toks.is_empty() {
        return Err(ExprError {
            what: "empty expression".into(),
            at: None,
        });
    }
    let mut p = Parser {
        toks,
        pos: 0,
        end: n + 1,
        names,
        depth: 0,
    };
    let e = p.expr()?;
    if p.pos < p.toks.len() {
        return Err(p.unexpected());
    }
    // the canonical text (the scene's key) writes parentheses the source may have left out;
    // it must read back, so its nesting is held to the same limit
    if e.canonical_depth() > MAX_DEPTH {
        return Err(ExprError {
            what: format!(
                "nested more than {MAX_DEPTH} deep once every sum, product, negation and \
                 power is in parentheses (as the canonical form writes it)"
            ),
            at: None,
        });
    }
    Ok(e)
}

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
    fn canonical_depth(&self) -> usize {
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
    use super::*;

    fn names() -> (Vec<String>, Vec<String>) {
        (
            vec!["x".into(), "y".into(), "phi".into()],
            vec!["m".into(), "g".into()],
        )
    }

    fn p(src: &str) -> Result<Expr, ExprError> {
        let (c, pa) = names();
        parse(
            src,
            &Names {
                coordinates: &c,
                parameters: &pa,
            },
        )
    }

    fn ev(src: &str, q: &[f64]) -> f64 {
        p(src).unwrap().eval(q, &[2.0, 9.81])
    }

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
    fn errors_have_positions() {
        let e = p("m*(x))").unwrap_err();
        assert_eq!(e.at, Some(6), "{e:?}");
        assert!(e.what.contains("`)`"));
        let e = p("abs(x)").unwrap_err();
        assert!(e.what.contains("not analytic") && e.at == Some(1), "{e:?}");
        let e = p("x + q").unwrap_err();
        assert!(
            e.what.contains("unknown name `q`") && e.what.contains("phi"),
            "{e:?}"
        );
        assert_eq!(e.at, Some(5));
        assert!(p("x^2000").unwrap_err().what.contains("1024"));
        assert!(p("1e999").unwrap_err().what.contains("not finite"));
        assert!(p("").is_err());
        assert!(p("sin x").is_err());
        assert!(p("x(2)").unwrap_err().what.contains("not a function"));
        assert!(p("atan2(x, y)")
            .unwrap_err()
            .what
            .contains("unknown function"));
        assert!(p("sin(x, y)").unwrap_err().what.contains("one argument"));
        assert!(p("(x").unwrap_err().what.contains("not closed"));
        let deep = "(".repeat(10_000) + "x" + &")".repeat(10_000);
        assert!(p(&deep).unwrap_err().what.contains("nested"));
        assert!(p(&"-".repeat(10_000)).is_err());
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
