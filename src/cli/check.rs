//! `tmc check`: read a mesh and report its topology checks.

use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use tmc::{Error, Result};

/// Check a mesh file (.ply, .obj, .off, .tmesh, .stl) and report the result.
///
/// Reports the mesh's topology checks (as text, or as one JSON object with
/// --json) on stdout. The exit status is 0 when the mesh is a consistently
/// oriented manifold (boundary edges, i.e. an open surface, are allowed),
/// and 1, after the report and with one line on stderr, when it has invalid
/// or degenerate triangles, non-manifold edges or vertices or
/// inconsistently oriented edges; also 1 if the file could not be read. A .tmesh file has every chunk's
/// checksum verified; a damaged chunk is named. STL cannot share vertices,
/// so topology checks on STL files are not meaningful; check a .ply, .obj,
/// .off or .tmesh file instead.
///
/// The report also counts zero-area triangles and vertices sharing a
/// position (with the numbers of the first few triangles of each); they
/// fail the check only with --strict.
///
/// An empty mesh (no triangles) is a manifold only vacuously: the report
/// says "closed manifold  yes (empty)" and a note on stderr gives its
/// counts; the exit status is 0, or 1 with --require-surface.
#[derive(Debug, Args)]
pub(crate) struct CheckArgs {
    /// The mesh to check (format from the extension or, failing that, the
    /// first bytes).
    #[arg(value_name = "MESH")]
    pub mesh: PathBuf,

    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,

    /// Fail (exit 1, after the report) when the mesh is empty: no
    /// triangles. Without it an empty mesh passes with a note on stderr.
    #[arg(long)]
    pub require_surface: bool,

    /// Fail (exit 1, after the report) also when a triangle has zero area
    /// or two vertices share a position.
    #[arg(long)]
    pub strict: bool,

    /// Print nothing on stderr but errors (no note on an empty mesh); the
    /// report on stdout is printed all the same.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `tmc check`.
pub(crate) fn run(args: &CheckArgs) -> Result<()> {
    let mesh = tmc::check::read_mesh(&args.mesh)?;
    let report = tmc::check::check_mesh(&mesh);
    super::output::to_stdout(|out| {
        if args.json {
            serde_json::to_writer(&mut *out, &report)?;
            writeln!(out)
        } else {
            report.print_text(out)
        }
    })?;
    if report.triangles == 0 {
        let empty = format!(
            "{}: the mesh is empty ({} vertices, 0 triangles)",
            args.mesh.display(),
            report.vertices
        );
        if args.require_surface {
            return Err(Error::Invalid(format!(
                "{empty}, and --require-surface asks for a surface"
            )));
        }
        if !args.quiet {
            say!("tmc: note: {empty}: closed only vacuously, there is no surface");
        }
    }
    if !report.is_oriented_manifold() {
        return Err(Error::Format(format!(
            "{}: not a consistently oriented manifold: {}",
            args.mesh.display(),
            report.defects()
        )));
    }
    if args.strict && !report.geometry.is_sound() {
        return Err(Error::Format(format!(
            "{}: --strict: {}",
            args.mesh.display(),
            report.geometry.defects()
        )));
    }
    Ok(())
}
