//! Readable `{:?}` of internal types that hold `inari::Interval`s (the Lohner sets): every
//! interval printed as the answers' [`crate::Interval`] prints, `[lo, hi]`. inari's own
//! `Debug` shows its SIMD representation (`__m128d(-lo, hi)`), which no reader should have
//! to decode.

use inari::Interval;
use std::fmt;

/// A field shown readably (see [`readable_debug`]).
pub(crate) struct Show<'a, T: ?Sized>(pub &'a T);

impl fmt::Debug for Show<'_, Interval> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&crate::Interval::from(*self.0), f)
    }
}

impl fmt::Debug for Show<'_, Vec<Interval>> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.0.iter().map(Show)).finish()
    }
}

impl fmt::Debug for Show<'_, Vec<Vec<Interval>>> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.0.iter().map(Show)).finish()
    }
}

impl fmt::Debug for Show<'_, Option<Interval>> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(x) => write!(f, "Some({:?})", Show(x)),
            None => f.write_str("None"),
        }
    }
}

/// `impl Debug` for a struct whose fields are listed with their kind: `iv` (an interval, or
/// a vector, matrix or option of them: shown by [`Show`]) or `dbg` (their own `Debug`).
macro_rules! readable_debug {
    ($ty:ident $(<$gen:ty>)? { $($field:ident: $kind:ident),* $(,)? }) => {
        impl std::fmt::Debug for $ty $(<$gen>)? {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                let mut d = f.debug_struct(stringify!($ty));
                $( $crate::readable::readable_debug!(@field d, self, $field, $kind); )*
                d.finish()
            }
        }
    };
    (@field $d:ident, $s:ident, $field:ident, iv) => {
        $d.field(stringify!($field), &$crate::readable::Show(&$s.$field));
    };
    (@field $d:ident, $s:ident, $field:ident, dbg) => {
        $d.field(stringify!($field), &$s.$field);
    };
}
pub(crate) use readable_debug;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::iv;

    struct Two {
        a: Interval,
        b: Vec<Vec<Interval>>,
        c: usize,
    }
    readable_debug!(Two {
        a: iv,
        b: iv,
        c: dbg
    });

    #[test]
    fn intervals_print_as_their_exact_endpoints() {
        let t = Two {
            a: iv(0.1, 0.30000000000000004),
            b: vec![vec![iv(-1.0, 2.5)], vec![]],
            c: 7,
        };
        assert_eq!(
            format!("{t:?}"),
            "Two { a: [0.1, 0.30000000000000004], b: [[[-1.0, 2.5]], []], c: 7 }"
        );
        assert_eq!(format!("{:?}", Show(&Interval::EMPTY)), "[empty]");
    }
}
