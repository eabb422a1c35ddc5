//! The Taylor coefficients a series returns ([`Coeffs`]) and borrowed views of their first
//! rows ([`Rows`]): one flat buffer, row `k` the coefficient `x_k` of every component.

/// Taylor coefficients `x_0 .. x_{len-1}`, each of `width` components, in one buffer: row
/// `k` is `x_k` ([spec eq. (2.2)](crate::spec::taylor)). [`Tape::ode_taylor`](super::Tape::ode_taylor)'s result.
#[derive(Clone, Debug, PartialEq)]
pub struct Coeffs<T> {
    pub(super) width: usize,
    pub(super) len: usize,
    pub(super) flat: Vec<T>,
}

/// Rows `0 .. len` of a [`Coeffs`], borrowed.
#[derive(Debug)]
pub struct Rows<'a, T> {
    pub(super) width: usize,
    pub(super) len: usize,
    pub(super) flat: &'a [T],
}

impl<T> Clone for Rows<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for Rows<'_, T> {}

impl<T: Copy> Coeffs<T> {
    /// Coefficients from rows of `width` entries each.
    pub fn from_rows<'a>(width: usize, rows: impl IntoIterator<Item = &'a [T]>) -> Self
    where
        T: 'a,
    {
        let mut flat = Vec::new();
        let mut len = 0;
        for r in rows {
            flat.extend_from_slice(&r[..width]);
            len += 1;
        }
        Coeffs { width, len, flat }
    }
    /// Every row.
    pub fn rows(&self) -> Rows<'_, T> {
        Rows {
            width: self.width,
            len: self.len,
            flat: &self.flat,
        }
    }
    /// The same coefficients through `f`, entry by entry.
    pub fn map<U>(&self, f: impl Fn(&T) -> U) -> Coeffs<U> {
        self.rows().map(f)
    }
    /// The number of rows (the order plus one).
    pub fn len(&self) -> usize {
        self.len
    }
    /// No rows.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// The rows, in order.
    pub fn iter(&self) -> impl DoubleEndedIterator<Item = &[T]> + ExactSizeIterator + '_ {
        self.rows().iter()
    }
}

impl<'a, T> Rows<'a, T> {
    /// The number of rows.
    pub fn len(&self) -> usize {
        self.len
    }
    /// No rows.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// The entries of a row.
    pub fn width(&self) -> usize {
        self.width
    }
    /// These rows through `f`, entry by entry.
    pub fn map<U>(self, f: impl Fn(&T) -> U) -> Coeffs<U> {
        Coeffs {
            width: self.width,
            len: self.len,
            flat: self.flat[..self.len * self.width].iter().map(f).collect(),
        }
    }
    /// The first `n` rows (all of them if there are fewer).
    pub fn first(self, n: usize) -> Rows<'a, T> {
        Rows {
            len: n.min(self.len),
            ..self
        }
    }
    /// Row `k`.
    pub fn row(self, k: usize) -> &'a [T] {
        assert!(k < self.len, "row {k} of {}", self.len);
        &self.flat[k * self.width..(k + 1) * self.width]
    }
    /// The rows, in order.
    pub fn iter(self) -> impl DoubleEndedIterator<Item = &'a [T]> + ExactSizeIterator {
        (0..self.len).map(move |k| self.row(k))
    }
}

impl<T: Copy> std::ops::Index<usize> for Coeffs<T> {
    type Output = [T];
    fn index(&self, k: usize) -> &[T] {
        self.rows().row(k)
    }
}

impl<T> std::ops::Index<usize> for Rows<'_, T> {
    type Output = [T];
    fn index(&self, k: usize) -> &[T] {
        self.row(k)
    }
}
