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
/// checksum verified; a damaged chunk is named. STL (binary or ASCII)
/// stores each facet's own corners, not shared vertices: its corners at
/// the same position (bit for bit, -0 as 0) are joined into one vertex, as
/// STL readers do, and that mesh is checked (with a note on stderr). For a
/// mesh tmc wrote that gives back its connectivity, but vertices of the
/// original mesh at one position become one vertex (non-manifold there,
/// and never counted as "sharing a position"); check the .ply, .obj, .off
/// or .tmesh file for the mesh itself.
///
/// The report also counts zero-area triangles and vertices sharing a
/// position (with the numbers of the first few triangles of each); they
/// fail the check only with --strict.
///
/// A .tmesh file is checked while its chunks stream, in memory bounded by
/// a few chunks (plus a few words per component), so that a mesh larger
/// than memory can be checked; vertices sharing a position are then
/// looked for among those of neighbouring chunks, where every file tmc
/// writes has them (--in-memory reads the mesh whole instead, as for the
/// other formats). Where the stream finds inconsistently oriented edges,
/// whether they can be oriented needs the whole mesh: it is read whole,
/// with a note on stderr.
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

    /// Read a .tmesh file whole into memory before checking it, instead of
    /// checking it while its chunks stream: vertices sharing a position
    /// are then looked for among all vertices, not only among those of
    /// neighbouring chunks. Memory grows with the mesh.
    #[arg(long)]
    pub in_memory: bool,

    /// Print nothing on stderr but errors (no note on an empty mesh or on
    /// reading a .tmesh whole); the report on stdout is printed all the
    /// same.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `tmc check`.
pub(crate) fn run(args: &CheckArgs) -> Result<()> {
    let report = report(args)?;
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

/// The report of `args.mesh`: streamed for a `.tmesh` file (but with
/// `--in-memory`, or where the stream cannot tell), read whole otherwise.
fn report(args: &CheckArgs) -> Result<tmc::check::MeshReport> {
    let path = &args.mesh;
    if !args.in_memory && tmc::check::is_tmesh(path)? {
        if let Some(report) = tmc::check::check_tmesh(path)? {
            return Ok(report);
        }
        if !args.quiet {
            say!(
                "tmc: note: {}: inconsistently oriented edges; reading the whole mesh into memory to tell whether they can be oriented",
                path.display()
            );
        }
    }
    if tmc::files::lowercase_extension(path) != "stl" {
        let mesh = tmc::check::read_mesh(path)?;
        return Ok(tmc::check::check_mesh(&mesh));
    }
    // STL stores each facet's own corners: they are joined by exact
    // position (as STL readers do) into the mesh that is checked.
    let mesh = tmc::check::read_mesh_to_draw(path)?;
    if !args.quiet {
        say!(
            "tmc: note: {}: STL shares no vertices; facet corners at the same position were joined into one vertex, so the report is of that mesh (vertices that shared a position in the mesh it was written from count as one)",
            path.display()
        );
    }
    Ok(tmc::check::check_mesh(&mesh))
}
