//! `tmc convert`: a `.tmesh` file to PLY, OBJ, OFF, STL (or `.tmesh`),
//! chunk by chunk.

use clap::Args;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use tmc::meshfile::TmeshReader;
use tmc::Result;

/// Convert a .tmesh file to .ply, .obj, .off, .stl (or .tmesh).
///
/// Reads one chunk at a time, so memory stays small whatever the mesh size.
/// The result is byte-identical to what 'tmc extract' writes in that format
/// directly. Every chunk's checksum is verified; a damaged file stops the
/// conversion with a message naming the chunk, and nothing is left at the
/// output path.
#[derive(Debug, Args)]
pub(crate) struct ConvertArgs {
    /// The .tmesh file, as written by 'tmc extract -o MESH.tmesh'.
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
    refuse_other_mesh(&args.input)?;
    tmc::part::PartRecord::refuse_part(&args.input)?;
    let mut reader = TmeshReader::open(&args.input)?;
    tmc::export::check_output_path(&args.output)?;
    if !args.quiet {
        if let Some(lost) = left_out(reader.info(), &args.output) {
            say!("tmc: note: {}: {lost}", args.output.display());
        }
    }
    let mut sink = tmc::export::create_sink(&args.output)?;
    let never = AtomicBool::new(false);
    tmc::export::replay_cancellable(&mut reader, sink.as_mut(), cancel.unwrap_or(&never))?;
    Ok(())
}

/// What an output format cannot hold of a mesh with `info`'s attributes:
/// per-face labels live only in PLY and `.tmesh`, vertex normals in PLY,
/// OBJ and `.tmesh`.
fn left_out(info: &tmc::MeshInfo, output: &std::path::Path) -> Option<String> {
    let ext = tmc::files::lowercase_extension(output);
    let labels = info.labels && !matches!(ext.as_str(), "ply" | "tmesh");
    let normals = info.normals && !matches!(ext.as_str(), "ply" | "obj" | "tmesh");
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

/// Refuses, saying what convert reads, an input that is another mesh
/// format by its extension and not a `.tmesh` by its first bytes (the
/// reader's 'wrong magic bytes' did not say that a PLY is not read).
fn refuse_other_mesh(input: &std::path::Path) -> Result<()> {
    let ext = tmc::files::lowercase_extension(input);
    if !matches!(ext.as_str(), "ply" | "obj" | "off" | "stl") {
        return Ok(());
    }
    let mut head = Vec::with_capacity(8);
    let read = std::fs::File::open(input).and_then(|f| {
        use std::io::Read;
        f.take(8).read_to_end(&mut head)
    });
    let readers = if ext == "stl" {
        "tmc preview reads .stl"
    } else {
        "tmc check and tmc preview read it"
    };
    match read {
        Ok(8) if head == tmc::meshfile::MAGIC => Ok(()),
        Ok(_) => Err(tmc::Error::Format(format!(
            "{}: a .{ext} file: tmc convert reads the .tmesh files that \
             'tmc extract -o MESH.tmesh' writes ({readers})",
            input.display()
        ))),
        // The reader names the I/O error.
        Err(_) => Ok(()),
    }
}
