//! Text shared by several `--help` pages.

/// Shared text at the end of `tmc --help` and `tmc extract --help`.
pub(crate) const CONVENTIONS: &str = "\
Sign convention:
  A sample is inside iff its value > ISO; a sample equal to ISO is outside, and
  NaN samples are outside. With --inside low the roles flip (inside iff value < ISO,
  for signed distance fields). Triangles are counter-clockwise seen from outside,
  so normals point toward the outside.

Input formats:
  .npy   numpy array of shape (nz, ny, nx) or (1, nz, ny, nx), C or Fortran
         order, dtype u1 i1 u2 i2 u4 i4 f4 f8 (also i8 u8 f2, read as f64, and
         bool as u1) in either byte order; unit spacing (set it with --spacing
         and --origin)
  .nrrd  NRRD, dimension 3, attached data or (also .nhdr) 'data file': one
  .nhdr  file, 'LIST [subdim]' (names on the following lines) or a printf
         pattern 'slice%03d.raw MIN MAX STEP [subdim]', one slice (subdim 2)
         or a block of slices (subdim 3) per file; encoding raw (mapped),
         gzip, bzip2, ascii or hex; any 8/16/32-bit integer type, float or
         double (64-bit integer types read as f64: exact within +-2^53);
         'line skip' and 'byte skip' (-1: data at the end) apply to each data
         file; grid from 'space directions' (rotation and mirroring applied)
         or 'spacings', origin from 'space origin' (or, without 'space
         directions', 'axis mins' as teem and ITK place it); lengths in
         'space units' or 'units' of metres, microns, nm ... ('microns'
         as Fiji writes them) converted to millimetres
  .nii   NIfTI-1/2, also .nii.gz and .hdr + .img; all integer types of 8 to
         32 bits, float, double (64-bit integer types read as f64);
         scl_slope/scl_inter applied (ISO in physical units); grid from the
         sform, else the qform, else pixdim (0 read as 1, with a note);
         lengths in metres or microns (xyzt_units) converted to millimetres
  .mhd   MetaImage, also .mha; ElementDataFile LOCAL, a file or LIST; zlib
         (CompressedData); HeaderSize; TransformMatrix, Offset, ElementSpacing;
         NDims 3, or 4 with a 4th DimSize of 1
  .vtk   legacy VTK STRUCTURED_POINTS, binary (big-endian) or ASCII
  .vti   VTK XML ImageData: ascii, binary or appended, raw or base64, zlib;
         Origin, Spacing, Direction
  .tif   a multi-page TIFF (or BigTIFF), or a directory or glob ('dir/*.tif')
         of single-page TIFFs in natural name order; 8/16/32-bit; spacing
         from ImageJ (unit=, spacing=, X/YResolution; origin from
         xorigin= ...) or OME-XML (PhysicalSizeX/Y/Z) metadata in
         millimetres, else unit spacing
  DICOM  a directory of slice files (DICM magic or .dcm; other files skipped),
         one slice file (its series in its directory) or a multi-frame .dcm;
         slices sorted by position along the normal, RescaleSlope/Intercept
         applied per slice (CT in HU), patient (LPS) coordinates; several
         series: 'tmc info DIR' lists them, --series N|UID picks one (other
         series, reports, plans, strays skipped: --verbose names them);
         RT Dose in its Dose Units (Gy); uncompressed, deflate, RLE, JPEG
         baseline/lossless, JPEG 2000 and HTJ2K (not JPEG-LS or JPEG XL:
         decompress those with 'gdcmconv --raw'); a Segmentation
         (SEG) as a label map of its segments (--labels all), or one segment
         as 0..1 with --segment N (--iso 0.5)
  Zarr   a Zarr v2 or v3 array in a directory store (STORE, or STORE/PATH for
         an array of a group, or --array PATH); blosc, zstd, gzip, zlib,
         bytes (either order), transpose, sharding; missing chunks read as
         the fill value; the last three axes are z, y, x, earlier ones must
         have one entry. OME-Zarr (NGFF 0.4, 0.5): level 0 or --level N,
         scale and translation as spacing and origin (in mm). Each chunk is
         decompressed once per pass, a layer of chunks at a time
  HDF5   a dataset of an HDF5 file (.h5, .hdf5, .nxs ...): FILE:/path/to/data
         or --dataset PATH; contiguous or chunked, gzip/deflate and shuffle;
         spacing from the dataset's element_size_um (z, y, x in um), in mm
  raw    headerless samples, x fastest: give --dims and --dtype
  Vertices are in the file's world frame (spacing, origin and direction
  cosines applied; a mirroring map flips the winding). --spacing and
  --origin set them for any input, overriding the file's (with a note). Uncompressed data is
  memory-mapped; gzip, bzip2 and zlib data is decompressed once into a
  temporary file in TMPDIR and mapped. 'tmc info' shows how a file is read.

Output formats (chosen by the extension of -o):
  .ply   binary little-endian, shared vertices
  .obj   text, shared vertices
  .off   text, shared vertices
  .stl   binary; STL cannot share vertices (each facet stores its own corners):
         'tmc check' joins corners at the same position into one vertex
  .tmesh tmc's chunked, compressed mesh (64-bit vertex numbers, checksums);
         'tmc convert' turns it into any format above, 'tmc check' reads it,
         scripts/read_tmesh.py reads it with numpy
  Meshes are streamed to the output as they are extracted, never held whole.
  The output is written atomically: on failure nothing is left at the path.

Exit status:
  0    success (also when the isovalue is outside the data range: a note on
       stderr and an empty mesh, unless --require-surface is given)
  1    failure (unreadable, malformed or changing input, unwritable output,
       disk full, --max-memory too small, ...; one line 'tmc: error: ...');
       'tmc check' also exits 1 when the mesh is not a consistently oriented
       manifold (non-manifold edges or vertices, inconsistent orientation)
       or, with --require-surface, when it is empty (no triangles);
       a batch ('tmc extract' with several inputs, isovalues or --manifest)
       exits 1 when any item failed, after naming each on stderr
  2    usage error (unknown option, missing or malformed value)
  130  interrupted by SIGINT, 143 by SIGTERM, 129 by SIGHUP: extract, convert,
       merge and synth stop at the next slab, chunk or plane (also while
       decompressing the input or assembling the output) and no output is
       left; a signal inherited as ignored (nohup, a background job of a
       script) stays ignored";
