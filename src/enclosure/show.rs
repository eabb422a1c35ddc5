//! Readable `{:?}` of internal types that hold intervals (the Lohner sets): every
//! interval printed as the answers' [`crate::Interval`] prints, `[lo, hi]`. inari's own
//! `Debug` shows its SIMD representation (`__m128d(-lo, hi)`), which no reader should have
//! to decode.

use super::ival::Ival;
#[cfg(test)]
use inari::Interval;
use std::fmt;

/// A field shown readably: an interval, or a vector, matrix or option of them, as `[lo, hi]`.
pub(crate) struct Show<'a, T: ?Sized>(pub &'a T);

impl<I: Ival> fmt::Debug for Show<'_, I> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.readable(f)
    }
}

impl<I: Ival> fmt::Debug for Show<'_, Vec<I>> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.0.iter().map(Show)).finish()
    }
}

impl<I: Ival> fmt::Debug for Show<'_, Vec<Vec<I>>> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.0.iter().map(Show)).finish()
    }
}

impl<I: Ival> fmt::Debug for Show<'_, Option<I>> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(x) => write!(f, "Some({:?})", Show(x)),
            None => f.write_str("None"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::iv;

    struct Two {
        a: Interval,
        b: Vec<Vec<Interval>>,
        c: usize,
    }
    impl fmt::Debug for Two {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.debug_struct("Two")
                .field("a", &Show(&self.a))
                .field("b", &Show(&self.b))
                .field("c", &self.c)
                .finish()
        }
    }

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
