//! The arguments of `tmc extract` (one run, a batch, a part), as clap
//! parses them, and what they mean for the library.

use super::help_text::CONVENTIONS;
use super::raw_input::RawArgs;
use super::{progress, values};
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use tmc::{ExtractParams, Inside, Method, PipelineOptions};

/// Extract the isosurface of a volume into a mesh file (several inputs or
/// isovalues in one batch; a label map's surfaces with --labels).
///
/// Streams the volume slab by slab on all cores and the mesh into the
/// output as it is made, so neither is held whole.
#[derive(Debug, Args)]
#[command(after_help = CONVENTIONS)]
pub(crate) struct ExtractArgs {
    /// Input volume: .npy, .nrrd, .nhdr, .nii, .nii.gz, .hdr, .mhd, .mha,
    /// .vtk, .vti, .tif/.tiff, a directory or pattern of TIFFs, DICOM (.dcm
    /// or a directory of slices), a Zarr store (STORE or STORE/ARRAY), or
    /// headerless samples with --dims and
    /// --dtype. Several inputs are a batch (see --keep-going): -o must
    /// contain {stem}.
    #[arg(value_name = "INPUT", required_unless_present = "manifest")]
    pub input: Vec<PathBuf>,

    /// Isovalue, a finite number. A sample is inside iff its value > ISO
    /// (equal is outside, NaN is outside). Several, comma-separated
    /// (--iso 550,1600), are extracted in one pass over the data, one output
    /// each: {iso} in -o is replaced by the isovalue, or '_iso<VALUE>' is
    /// inserted before the extension.
    #[arg(long, value_name = "VALUE", allow_hyphen_values = true, value_parser = values::finite,
          value_delimiter = ',', required_unless_present_any = ["manifest", "labels"])]
    pub iso: Vec<f64>,

    /// Segmentation label map: instead of an isosurface, the boundary
    /// surface of each label L (the isosurface at 0.5 of the indicator
    /// 'value == L', with the same rules and ties, so each label's mesh is
    /// what an extraction of its 0/1 volume at --iso 0.5 writes), all
    /// labels in one pass. 'all' is every value present but the background
    /// (--background, 0 by default), found by a first reading of the
    /// volume; or a list L1,L2,... -o must contain {label} (one file per
    /// label) or be one .ply or .tmesh (every label, a per-face uint32
    /// 'label'). With --part I/N, -o must hold {label} and {part} and end
    /// in .tmesh, the same for every part ('parts/{label}.{part}.tmesh':
    /// one part file per label and part; 'tmc merge' of all of them writes
    /// what one run writes). With --normals, each label's normals are those of its
    /// indicator's gradient. A label's surface faces out of its samples
    /// (--inside low is refused). Float inputs must hold whole numbers (the first
    /// sample that does not is an error). --stats/--json give per label
    /// triangles, components, genus, area and (closed surfaces) enclosed volume beside the
    /// label's voxel count times the voxel volume. --preview draws every
    /// label's surface into one picture.
    #[arg(long, value_name = "all|L1,L2,...", allow_hyphen_values = true,
          conflicts_with_all = ["iso", "manifest", "require_surface"],
          value_parser = values::label_spec)]
    pub labels: Option<values::LabelSpec>,

    /// With --labels all: the value that is no label (0 by default); a
    /// whole number, which a float map's may be written as (-1.0). Refused
    /// with a list of labels, where it would change nothing.
    #[arg(
        long,
        value_name = "V",
        requires = "labels",
        // `requires` alone lets `--iso V --background B` through (clap
        // waives it when the required argument conflicts with one given).
        conflicts_with_all = ["iso", "manifest"],
        allow_hyphen_values = true,
        value_parser = values::label
    )]
    pub background: Option<i64>,

    /// Output mesh; the format comes from the extension: .ply, .obj, .off,
    /// .stl or .tmesh (chunked and compressed, any size; see 'tmc convert').
    /// Streamed as it is extracted; written atomically: nothing is left there
    /// if the run fails. {stem} is replaced by the input's name without its
    /// extension(s) (an HDF5 file's, also for FILE.h5:/dataset; a Zarr
    /// store's, also for STORE.zarr/array), {iso} by the isovalue, {label}
    /// by the label (--labels), {part} by I (--part I/N). Any other {NAME}
    /// is an error; other braces are kept.
    #[arg(
        short,
        long,
        value_name = "OUTPUT",
        required_unless_present = "manifest"
    )]
    pub output: Option<PathBuf>,

    /// Also draw the mesh into a PNG picture (1024x1064: three orthogonal
    /// views and one oblique, shaded, captioned with the input's name, the
    /// isovalue, the triangle count and closed/genus), rendered while the
    /// mesh streams; written atomically. {stem} and {iso} as in -o. The
    /// same bytes for any --threads and --slab-depth, and those of 'tmc
    /// preview MESH.tmesh --title INPUT-NAME'. With --labels, one picture of
    /// every label's surface, each in its label's colour (its number modulo
    /// 16), captioned with the number of labels and the verdict of all the
    /// surfaces together ({stem} as in -o).
    #[arg(long, value_name = "FILE.png")]
    pub preview: Option<PathBuf>,

    /// Cell algorithm.
    #[arg(long, value_enum, default_value_t = MethodArg::Tmc)]
    pub method: MethodArg,

    /// Which side of the isovalue is the object.
    #[arg(long, value_enum, default_value_t = InsideArg::High)]
    pub inside: InsideArg,

    /// Treat everything beyond the volume as outside, so every surface is
    /// closed (surfaces are otherwise open where they leave the volume).
    #[arg(long)]
    pub close: bool,

    /// Give every vertex a unit outward normal, from the field's gradient
    /// (central differences at the samples, linear along the vertex's edge,
    /// in world coordinates; where it vanishes, the angle-weighted normal of
    /// the vertex's triangles): PLY 'nx ny nz', OBJ 'vn' with faces 'v//vn',
    /// .tmesh an optional attribute; OFF and STL have no vertex normals and
    /// are refused.
    #[arg(long)]
    pub normals: bool,

    /// Print the cell statistics (the paper's Table 1), sizes and time to
    /// stderr as a table.
    #[arg(long)]
    pub stats: bool,

    /// Print one JSON object on stdout: the run's parameters, the grid and all
    /// statistics. In a batch: one JSON line per input (see --report).
    #[arg(long)]
    pub json: bool,

    /// Worker threads, at most 1024 (and no more are started than there
    /// are cell layers); 0 (the default) uses all cores.
    #[arg(long, value_name = "N", value_parser = values::threads)]
    pub threads: Option<usize>,

    /// Cell layers per slab (1 to 64; a slab is the unit of parallel work);
    /// by default about 64 M samples per slab, 16 to 64 layers, and with
    /// several threads about sixteen slabs per thread (at least 8 layers
    /// each). Memory grows with it; the output does not depend on it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=64))]
    pub slab_depth: Option<u16>,

    /// Bound the pipeline's memory to about BYTES (suffixes K, M, G, T:
    /// powers of 1024): the workers' buffers are planned to fit (an error if
    /// they do not beside one slab of 2 layers per worker), and a slab
    /// starts only when the mesh measured in flight leaves room for it (one
    /// layer always may). The memory-mapped input is not counted. The
    /// output does not depend on it.
    #[arg(long, value_name = "BYTES", value_parser = values::bytes)]
    pub max_memory: Option<u64>,

    /// Fail (exit 1, no output) when there is no surface, i.e. every
    /// sample is on the same side of the isovalue. Without it such a run
    /// writes an empty mesh, prints a note and exits 0. Not with --part: a
    /// part may hold no surface when the volume has one; check the merged
    /// mesh with 'tmc check --require-surface'.
    #[arg(long, conflicts_with = "part")]
    pub require_surface: bool,

    /// Print nothing on stderr but errors (no progress bar). A progress bar
    /// is shown otherwise, when stderr is a terminal.
    #[arg(short, long, conflicts_with = "stats")]
    pub quiet: bool,

    /// Progress on stderr: 'auto' a bar when stderr is a terminal; 'lines'
    /// a line at every 10% of the cell layers and at least every 30 s, with
    /// the time taken and the ETA (for the log of a batch job); 'never'.
    #[arg(
        long,
        value_name = "WHEN",
        value_enum,
        default_value_t,
        conflicts_with = "quiet"
    )]
    pub progress: progress::ProgressMode,

    /// Batch: --manifest, --report, --keep-going.
    #[command(flatten)]
    pub batch: BatchArgs,

    /// Extract only part I of N (e.g. 3/7): the I-th of N z-ranges of cell
    /// layers, written as a part file for 'tmc merge' (see docs/hpc.md).
    /// One input and one isovalue only. {part} in -o is replaced by I, so
    /// every part can be given the same -o ('parts/p{part}.tmesh'); with
    /// --labels it is required.
    #[arg(long, value_name = "I/N", value_parser = tmc::part::PartSpec::parse)]
    pub part: Option<tmc::part::PartSpec>,

    /// Headerless input: --dims, --dtype, --endian, ...
    #[command(flatten)]
    pub raw: RawArgs,
}

/// `--method`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum MethodArg {
    /// Grosso's topologically correct and manifold hybrid marching cubes.
    Tmc,
    /// Standard marching cubes with one fixed rule for ambiguous faces
    /// (crack-free, but not topologically correct).
    Mc,
}

/// `--inside`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum InsideArg {
    /// Values above the isovalue are inside (CT, MRI, densities).
    High,
    /// Values below the isovalue are inside (signed distance fields).
    Low,
}

impl ExtractArgs {
    /// The extraction parameters at isovalue `iso`.
    pub(super) fn params(&self, iso: f64) -> ExtractParams {
        ExtractParams {
            iso,
            method: match self.method {
                MethodArg::Tmc => Method::Tmc,
                MethodArg::Mc => Method::Mc,
            },
            inside: match self.inside {
                InsideArg::High => Inside::High,
                InsideArg::Low => Inside::Low,
            },
            close: self.close,
            threads: self.threads.unwrap_or(0),
            normals: self.normals,
        }
    }
}

impl ExtractArgs {
    /// With `--normals`, fails unless `output`'s format holds vertex
    /// normals (OFF and STL do not: the run would compute them for
    /// nothing).
    pub(super) fn check_normals_output(&self, output: &std::path::Path) -> tmc::Result<()> {
        tmc::export::check_normals_output(output, self.normals)
    }

    /// How the pipeline runs for these arguments.
    pub(super) fn pipeline_options<'a>(
        &self,
        progress: &'a (dyn Fn(&tmc::Progress) + Sync),
        cancel: Option<&'a AtomicBool>,
    ) -> PipelineOptions<'a> {
        PipelineOptions {
            slab_depth: self.slab_depth.map_or(0, usize::from),
            progress: Some(progress),
            cancel,
            max_memory: self.max_memory,
            vertex_values: None,
        }
    }
}

/// The batch options of `tmc extract`.
#[derive(Debug, Args)]
pub(crate) struct BatchArgs {
    /// Read the inputs from FILE, one per line: 'INPUT ISO[,ISO...] OUTPUT'
    /// separated by whitespace, or by tabs when the line has one (paths with
    /// spaces); '#' starts a comment line. OUTPUT may use {stem} and {iso}
    /// (any other {NAME} is an error naming FILE:LINE).
    /// Relative paths are relative to the current directory.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["input", "iso", "output"])]
    pub manifest: Option<PathBuf>,

    /// Append one JSON line per input to FILE (as --json does on stdout):
    /// input, outputs, isos, status ("ok" or "failed"), error, triangles and
    /// vertices per output, seconds, manifest line.
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,

    /// In a batch, go on with the next input after a failure (without it,
    /// the batch stops at the first failed input). Either way the exit
    /// status is 1 when any input failed, and each is named on stderr.
    #[arg(long)]
    pub keep_going: bool,
}

impl BatchArgs {
    /// Whether a batch option was given (a batch even with one input).
    pub(crate) fn given(&self) -> bool {
        self.manifest.is_some() || self.report.is_some()
    }
}
