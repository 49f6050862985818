//! [`RowField`]: what every synthetic field implements, so that
//! [`Synthetic`](super::Synthetic) can evaluate any of them a row at a time.

/// A field evaluated one row (fixed y and z, x varying) at a time.
pub(crate) trait RowField: Send + Sync {
    /// Data shared by the rows of plane `z`, computed once per plane
    /// (nothing by default).
    fn plane(&self, _z: usize) -> Vec<f64> {
        Vec::new()
    }
    /// Writes the field at `(0.., y, z)` into `out` (length `dims[0]`);
    /// `plane` is what [`RowField::plane`] returned for `z`.
    fn row(&self, plane: &[f64], y: usize, z: usize, out: &mut [f64]);
}
