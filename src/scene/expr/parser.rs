//! The parser: tokens to an [`Expr`] tree by recursive descent, with every name resolved
//! to a coordinate, a parameter, a function or `pi`, and the nesting held to [`MAX_DEPTH`].

use super::lexer::{describe, shown, tokenize, Tok};
use super::{
    Exponent, Expr, ExprError, Func, Names, FUNCTIONS, MAX_DEPTH, MAX_INT_EXPONENT, MAX_LEN,
    NOT_ANALYTIC,
};

/// A parse in progress: the tokens and the next one, the position past the end (for
/// messages), the names to resolve, and the nesting depth so far.
struct Parser<'a> {
    toks: Vec<(Tok, usize)>,
    pos: usize,
    end: usize,
    names: &'a Names<'a>,
    depth: usize,
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
            Some((t, at)) => {
                // `**` (Python's power): say how powers are written
                let star = Tok::Op('*');
                let power = *t == star
                    && self.pos > 0
                    && self.toks.get(self.pos - 1) == Some(&(star, at.wrapping_sub(1)));
                ExprError {
                    what: if power {
                        format!(
                            "unexpected {}: powers are written `^` (`x^2`), not `**`",
                            describe(t)
                        )
                    } else {
                        format!("unexpected {}", describe(t))
                    },
                    at: Some(*at),
                }
            }
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

#[cfg(test)]
mod tests {
    use super::super::test_names::p;

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
}
