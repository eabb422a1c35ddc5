//! Expressions of scene files ([spec/10-scene-files.md](crate::spec::scene_files), "Expressions"): parsed once into a
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
//!
//! One concern a file: `lexer` (characters to tokens), `parser` (tokens to a tree with its
//! names resolved), `eval` (the evaluator and the canonical printer), `sym` (the symbolic
//! scalar that writes formulas).

mod eval;
mod lexer;
mod parser;
mod sym;

pub use lexer::shown;
pub use parser::parse;
pub use sym::Sym;

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
    /// Coordinate `q[i]`.
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

/// Helpers of the tests of this module's files: a parse with fixed names.
#[cfg(test)]
mod test_names {
    use super::{parse, Expr, ExprError, Names};

    pub(super) fn names() -> (Vec<String>, Vec<String>) {
        (
            vec!["x".into(), "y".into(), "phi".into()],
            vec!["m".into(), "g".into()],
        )
    }

    pub(super) fn p(src: &str) -> Result<Expr, ExprError> {
        let (c, pa) = names();
        parse(
            src,
            &Names {
                coordinates: &c,
                parameters: &pa,
            },
        )
    }

    pub(super) fn ev(src: &str, q: &[f64]) -> f64 {
        p(src).unwrap().eval(q, &[2.0, 9.81])
    }
}
