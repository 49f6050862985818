//! `tmc preview`: the picture `tmc extract --preview` draws, of an existing
//! mesh file.

use super::values;
use clap::Args;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use tmc::meshfile::TmeshReader;
use tmc::preview::PreviewSink;
use tmc::Result;

/// Draw a mesh into a PNG picture: three orthogonal views and one oblique.
///
/// A .tmesh file is read one chunk at a time, so any size works, and the
/// picture is framed by the volume's box recorded in it: the bytes are
/// those 'tmc extract --preview' wrote for the same mesh (give --title the
/// input's name). A .tmesh keeps no direction cosines: a mesh extracted on
/// a rotated or mirrored grid that leaves the recorded box is read a
/// second time and framed by its vertices' box (with a note on stderr).
/// PLY, OBJ, OFF and STL files are read whole and framed by their
/// vertices' box (an STL's facet corners at the same position are joined
/// into one vertex, so the caption counts its boundary edges and
/// components as for the mesh it was written from).
#[derive(Debug, Args)]
pub(crate) struct PreviewArgs {
    /// The mesh: .tmesh (streamed), .ply, .obj, .off or .stl, binary or
    /// ASCII (read whole).
    #[arg(value_name = "MESH")]
    pub input: PathBuf,

    /// The picture, a .png file; written atomically.
    #[arg(short, long, value_name = "FILE.png")]
    pub output: PathBuf,

    /// The first caption line (default: the mesh's file name).
    #[arg(long, value_name = "TEXT")]
    pub title: Option<String>,

    /// Drawing threads; 0 (the default) uses all cores. The bytes do not
    /// depend on it.
    #[arg(long, value_name = "N", value_parser = values::threads)]
    pub threads: Option<usize>,

    /// Print nothing on stderr but errors (no note when a .tmesh is read a
    /// second time to frame it).
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `tmc preview`; setting `cancel` stops it before the next chunk with
/// [`tmc::Error::Interrupted`], leaving no picture.
pub(crate) fn run(args: &PreviewArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    // No placeholder is filled in: a `{NAME}` would stay in the name.
    super::placeholders::check(&args.output, "-o", &[])?;
    tmc::files::check_input_kind(&args.input)?;
    tmc::preview::check_png_path(&args.output)?;
    tmc::files::check_distinct(&args.input, &args.output)?;
    let title = args
        .title
        .clone()
        .unwrap_or_else(|| tmc::preview::title_of(&args.input));
    let threads = args.threads.unwrap_or(0);
    let never = AtomicBool::new(false);
    let cancel = cancel.unwrap_or(&never);
    if tmc::files::lowercase_extension(&args.input) == "tmesh" {
        tmc::part::PartRecord::refuse_part(&args.input)?;
        let mut reader = TmeshReader::open(&args.input)?;
        let mut sink =
            PreviewSink::new(args.output.clone(), title, None, threads).with_recorded_grid();
        tmc::export::replay_cancellable(&mut reader, &mut sink, cancel)?;
        if let Some(mut again) = sink.reframed() {
            if !args.quiet {
                say!(
                    "tmc: note: {}: the mesh leaves the box of the grid recorded with it \
                     (a rotated or mirrored grid: a .tmesh keeps no direction); \
                     read again and framed by its own box",
                    args.input.display()
                );
            }
            let mut reader = TmeshReader::open(&args.input)?;
            tmc::export::replay_cancellable(&mut reader, &mut again, cancel)?;
        }
        return Ok(());
    }
    let mesh = tmc::check::read_mesh_to_draw(&args.input)?;
    tmc::preview::draw_mesh(mesh, &args.output, title, threads, cancel)
}
