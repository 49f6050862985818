//! `tmc convert`: a `.tmesh` file to PLY, OBJ, OFF, STL (or `.tmesh`),
//! chunk by chunk; a PLY, OBJ, OFF or STL file, read whole, to another of
//! those formats.

use clap::Args;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use tmc::meshfile::TmeshReader;
use tmc::Result;

/// Convert a mesh file: .tmesh to .ply, .obj, .off, .stl (or .tmesh), and
/// .ply, .obj, .off or .stl to .ply, .obj, .off or .stl.
///
/// A .tmesh file is read one chunk at a time, so memory stays small
/// whatever the mesh size, and the result is byte-identical to what 'tmc
/// extract' writes in that format directly. Every chunk's checksum is
/// verified; a damaged file stops the conversion with a message naming the
/// chunk, and nothing is left at the output path.
///
/// Other mesh files are read whole (memory grows with the mesh). PLY keeps
/// vertex normals (nx ny nz) and a face 'label'; OBJ keeps one normal per
/// vertex; STL's facet corners at one position become one vertex. A .tmesh
/// file cannot be made from them: it records the extraction that made it.
#[derive(Debug, Args)]
pub(crate) struct ConvertArgs {
    /// The mesh file: a .tmesh file, as written by 'tmc extract -o
    /// MESH.tmesh', or a .ply, .obj, .off or .stl file.
    #[arg(value_name = "INPUT")]
    pub input: PathBuf,

    /// Output mesh; the format comes from the extension: .ply, .obj, .off,
    /// .stl or .tmesh. Written atomically: nothing is left there if the run
    /// fails.
    #[arg(short, long, value_name = "OUTPUT")]
    pub output: PathBuf,

    /// Print nothing on stderr but errors (the only other line is a note
    /// that the output format leaves out the input's labels or normals).
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `tmc convert`; setting `cancel` (SIGINT, SIGTERM) stops it before
/// the next chunk with [`tmc::Error::Interrupted`], leaving no output.
pub(crate) fn run(args: &ConvertArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    // No placeholder is filled in: a `{NAME}` would stay in the name.
    super::placeholders::check(&args.output, "-o", &[])?;
    tmc::files::check_distinct(&args.input, &args.output)?;
    if is_other_mesh(&args.input) {
        return convert_whole(args, cancel);
    }
    tmc::part::PartRecord::refuse_part(&args.input)?;
    let mut reader = TmeshReader::open(&args.input)?;
    tmc::export::check_output_path(&args.output)?;
    let info = reader.info();
    note_left_out(args, info.labels, info.normals);
    let mut sink = tmc::export::create_sink(&args.output)?;
    let never = AtomicBool::new(false);
    tmc::export::replay_cancellable(&mut reader, sink.as_mut(), cancel.unwrap_or(&never))?;
    Ok(())
}

/// Converts a PLY, OBJ, OFF or STL file, read whole, into the output's
/// format (not `.tmesh`, which records an extraction).
fn convert_whole(args: &ConvertArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    if tmc::export::Format::from_path(&args.output)? == tmc::export::Format::Tmesh {
        return Err(tmc::Error::Invalid(format!(
            "{}: a .tmesh file records the extraction that made it, and {} is \
             another mesh format: write .ply, .obj, .off or .stl (or extract \
             the volume again with -o MESH.tmesh)",
            args.output.display(),
            args.input.display()
        )));
    }
    tmc::export::check_output_path(&args.output)?;
    let mesh = tmc::check::read_mesh_to_draw(&args.input)?;
    if cancel.is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed)) {
        return Err(tmc::Error::Interrupted);
    }
    note_left_out(args, mesh.labels.is_some(), mesh.normals.is_some());
    tmc::export::write_mesh(&args.output, &mesh)
}

/// Says on stderr (unless `-q`) what the output format leaves out.
fn note_left_out(args: &ConvertArgs, labels: bool, normals: bool) {
    if !args.quiet {
        if let Some(lost) = left_out(labels, normals, &args.output) {
            say!("tmc: note: {}: {lost}", args.output.display());
        }
    }
}

/// What an output format cannot hold of a mesh with per-face `labels` or
/// vertex `normals`: labels live only in PLY and `.tmesh`, normals in PLY,
/// OBJ and `.tmesh`.
fn left_out(labels: bool, normals: bool, output: &std::path::Path) -> Option<String> {
    let ext = tmc::files::lowercase_extension(output);
    let labels = labels && !matches!(ext.as_str(), "ply" | "tmesh");
    let normals = normals && !matches!(ext.as_str(), "ply" | "obj" | "tmesh");
    let (what, keep) = match (labels, normals) {
        (true, true) => (
            "per-face labels and vertex normals",
            ".ply and .tmesh keep them",
        ),
        (true, false) => ("per-face labels", ".ply and .tmesh keep them"),
        (false, true) => ("vertex normals", ".ply, .obj and .tmesh keep them"),
        (false, false) => return None,
    };
    Some(format!(
        "a .{ext} file has no place for the input's {what}: left out ({keep})"
    ))
}

/// Whether `input` is a PLY, OBJ, OFF or STL file by its extension and
/// not a `.tmesh` file by its first bytes (a `.tmesh` file renamed `.ply`
/// is still streamed). An unreadable file goes to the `.tmesh` reader,
/// which names the I/O error.
fn is_other_mesh(input: &std::path::Path) -> bool {
    let ext = tmc::files::lowercase_extension(input);
    if !matches!(ext.as_str(), "ply" | "obj" | "off" | "stl") {
        return false;
    }
    let mut head = Vec::with_capacity(8);
    let read = std::fs::File::open(input).and_then(|f| {
        use std::io::Read;
        f.take(8).read_to_end(&mut head)
    });
    matches!(read, Ok(n) if n < 8 || head != tmc::meshfile::MAGIC)
}
