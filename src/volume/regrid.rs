//! `--spacing` and `--origin` for every input: [`Regridded`] reads the
//! samples of another source on a grid with another spacing or origin.
//!
//! Where the file states no spacing or origin (a `.npy`, a TIFF without
//! voxel size, headerless samples) the option sets it; where it states one
//! the option overrides it, and [`regrid`] says so in a note for the user.
//! The direction cosines are kept: only the spacing along each index axis
//! and the position of sample (0, 0, 0) change. The samples are untouched,
//! so every other question is passed on to the source.

use super::{SampleSource, SourceNotes, ValueFrom};
use crate::grid::Grid;
use crate::{Error, Result};

/// A source read on another grid (see the module documentation).
pub struct Regridded {
    inner: Box<dyn SampleSource>,
    grid: Grid,
    notes: SourceNotes,
}

/// `inner` with `spacing` and `origin` replacing its grid's where given
/// (spacing finite and positive, origin finite), and the notes for the
/// user: one line per value of the file's that was overridden. With
/// neither given, `inner` comes back as it was.
pub fn regrid(
    inner: Box<dyn SampleSource>,
    spacing: Option<[f64; 3]>,
    origin: Option<[f64; 3]>,
) -> Result<(Box<dyn SampleSource>, Vec<String>)> {
    if spacing.is_none() && origin.is_none() {
        return Ok((inner, Vec::new()));
    }
    if let Some(s) = spacing.filter(|s| s.iter().any(|v| !v.is_finite() || *v <= 0.0)) {
        return Err(Error::Invalid(format!(
            "spacing {s:?} must be finite and positive"
        )));
    }
    if let Some(o) = origin.filter(|o| o.iter().any(|v| !v.is_finite())) {
        return Err(Error::Invalid(format!("origin {o:?} must be finite")));
    }
    let mut grid = *inner.grid();
    let mut notes = inner.notes();
    let mut said = Vec::new();
    let mut set = |name: &str, value: [f64; 3], old: &mut [f64; 3], from: &mut ValueFrom| {
        let stated = match from {
            ValueFrom::File { what } => {
                said.push(format!(
                    "--{name} {} overrides the {name} {} stated by the file ({what})",
                    join(value),
                    join(*old)
                ));
                Some(*old)
            }
            ValueFrom::Default | ValueFrom::Option { .. } => None,
        };
        *old = value;
        *from = ValueFrom::Option { file: stated };
    };
    if let Some(s) = spacing {
        set("spacing", s, &mut grid.spacing, &mut notes.spacing_from);
    }
    if let Some(o) = origin {
        set("origin", o, &mut grid.origin, &mut notes.origin_from);
    }
    Ok((Box::new(Regridded { inner, grid, notes }), said))
}

/// `x,y,z` as the options take it.
fn join(triple: [f64; 3]) -> String {
    triple.map(crate::params::number_text).join(",")
}

impl SampleSource for Regridded {
    super::forward_to_inner!(
        read_plane,
        lend_plane,
        share_plane,
        advise,
        check_unchanged,
        interrupted,
        data_files,
        sample_bytes,
        stored_type,
        plane_memory,
    );

    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn notes(&self) -> SourceNotes {
        self.notes.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::ArrayVolume;

    fn source() -> Box<dyn SampleSource> {
        let grid = Grid {
            spacing: [1.0, 2.0, 3.0],
            origin: [5.0, 6.0, 7.0],
            ..Grid::unit([2, 2, 2])
        };
        Box::new(ArrayVolume::new(grid, (0..8).map(f64::from).collect()).unwrap())
    }

    #[test]
    fn a_far_spacing_is_said_with_an_exponent() {
        let (_, notes) = regrid(source(), Some([1e-300, 1.0, 1e300]), None).unwrap();
        assert!(
            notes[0].starts_with("--spacing 1e-300,1,1e300 overrides"),
            "{notes:?}"
        );
    }

    #[test]
    fn spacing_overrides_the_file_and_says_so_origin_stays() {
        let (s, notes) = regrid(source(), Some([0.5, 0.5, 2.0]), None).unwrap();
        assert_eq!(s.grid().spacing, [0.5, 0.5, 2.0]);
        assert_eq!(s.grid().origin, [5.0, 6.0, 7.0]);
        assert_eq!(notes.len(), 1);
        assert!(
            notes[0].contains("overrides the spacing 1,2,3"),
            "{notes:?}"
        );
        assert_eq!(
            s.notes().spacing_from,
            ValueFrom::Option {
                file: Some([1.0, 2.0, 3.0])
            }
        );
        assert_eq!(s.notes().origin_from, ValueFrom::header());
        let mut plane = vec![0.0; 4];
        s.read_plane(1, &mut plane).unwrap();
        assert_eq!(plane, [4.0, 5.0, 6.0, 7.0]);
    }

    #[test]
    fn bad_values_are_refused_and_none_leaves_the_source_alone() {
        assert!(regrid(source(), Some([1.0, 0.0, 1.0]), None).is_err());
        assert!(regrid(source(), None, Some([f64::NAN, 0.0, 0.0])).is_err());
        let (s, notes) = regrid(source(), None, None).unwrap();
        assert!(notes.is_empty());
        assert_eq!(s.grid().spacing, [1.0, 2.0, 3.0]);
    }
}
