//! The lexer: the characters of an expression to tokens with their 1-based positions.

use super::ExprError;

/// A token: a number (its value and its text), a name, or an operator or parenthesis.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Tok {
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

pub(super) fn tokenize(src: &str) -> Result<Vec<(Tok, usize)>, ExprError> {
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

/// A token as a message names it.
pub(super) fn describe(t: &Tok) -> String {
    match t {
        Tok::Num(_, s) => format!("number `{}`", shown(s, 40)),
        Tok::Name(s) => format!("name `{}`", shown(s, 40)),
        Tok::Op(c) => format!("`{c}`"),
    }
}
