//! `quadrille`: the command-line front of Quadrille.
//!
//! Subcommands: `info` (what a CAD model holds), `mesh` (mesh a model),
//! `stats` (judge any mesh, ours or another mesher's), `render` (draw a mesh),
//! `field` (the cross field, singularities and relation (2) of every face).
//! Every error is printed as one clear message naming the file and the
//! problem, with a non-zero exit code; no partial output file is left behind.

mod cmd_coarse;
mod cmd_curves;
mod cmd_field;
mod cmd_info;
mod cmd_mesh;
mod cmd_render;
mod cmd_spline;
mod cmd_spline_cones;
mod cmd_stats;
mod files;
mod progress;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

const EXAMPLES: &str = "\
Examples:
  quadrille info part.step
  quadrille mesh part.step -o part.msh --png part.png
  quadrille mesh part.step -o part.msh --size-factor 0.5 --threads 2
  quadrille mesh part.step -o part.msh --no-cavities --timings
  quadrille mesh scan.stl -o scan.msh --feature-angle 40
  quadrille stats part.msh --cad part.step
  quadrille stats other_mesher.msh --json
  quadrille render part.msh -o part.png --sicn
  quadrille field part.step -o field.vtu --png field.png --json
  quadrille field part.step --json > field.json";

/// Quadrilateral meshes of CAD models (STEP, IGES, BREP) and of triangle
/// meshes (STL, OBJ, PLY, MSH), read as a B-rep of feature curves and faces.
#[derive(Parser, Debug)]
#[command(name = "quadrille", version, about, after_help = EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Show what a model (CAD or triangle mesh) holds: corners, curves, faces, loops, seams.
    #[command(
        after_help = "Examples:\n  quadrille info part.step --json\n  quadrille info scan.stl --feature-angle 40"
    )]
    Info(InfoArgs),
    /// Mesh a CAD model (STEP, IGES, BREP) or a triangle mesh (STL, OBJ, PLY, MSH) with quads and write MSH, VTU or OBJ.
    #[command(
        after_help = "Examples:\n  quadrille mesh part.step -o part.msh\n  quadrille mesh scan.stl -o scan.msh --feature-angle 40\n  quadrille mesh part.step -o part.vtu --size 2.5 --png part.png\n  quadrille mesh part.step -o part.msh --method unstructured --timings\n  quadrille mesh part.step -o part.msh --no-patterns --no-cavities\n  quadrille mesh part.step -o part.msh --method coarse --order 5 --png part.png --json"
    )]
    Mesh(MeshArgs),
    /// Quality statistics of a mesh (MSH 4.1 or 2.2): SICN, valences, irregular vertices, open edges.
    #[command(
        after_help = "Examples:\n  quadrille stats part.msh\n  quadrille stats part.msh --cad part.step --json"
    )]
    Stats(StatsArgs),
    /// Draw a mesh (MSH) to a PNG picture: shaded quads, edges, irregular vertices.
    #[command(after_help = "Example:\n  quadrille render part.msh -o part.png --sicn")]
    Render(RenderArgs),
    /// Cross field of every face on its background triangulation: VTU file,
    /// optional picture, singularities and the check of Eq. (2) of the paper.
    #[command(
        long_about = "Computes the boundary-aligned cross field of every face of a model (CAD or triangle mesh) on the \
background triangulation the mesher uses (3 times finer than the quad size), its singularities \
and the check of relation (2) of the quasi-structured paper: the singularity indices plus the \
corner indices (2 - ideal valence) of a face add up to 4 times its Euler characteristic.\n\n\
The VTU file holds the background triangles, then one vertex cell per singularity, with \
cell data cad_face, cross (one unit branch of the cross, for glyphs), size (the conformal \
size map) and singularity_index (0 on triangles, +1 or -1 on singularities).",
        after_help = "Examples:\n  quadrille field part.step -o field.vtu --png field.png\n  quadrille field part.step --json > field.json\n  quadrille field part.step -o field.vtu --json --size-factor 0.5 --quiet\n  quadrille field part.step -o field.vtu --size-png size.png --entity-size curve:3=0.05"
    )]
    Field(FieldArgs),
    /// Quads from the closed cycles of a 3D curve network (JSON, OBJ lines, or a CAD model's face
    /// boundaries), with no surface given; see docs/curve-networks.md.
    #[command(
        after_help = "Examples:\n  quadrille curves net.json -o net.msh --png net.png\n  quadrille curves part.step --faces 1,4 -o faces.msh --json\n  quadrille curves net.obj --check\n  quadrille curves net.json -o net.vtu --size 0.05 --skip-bad --timings"
    )]
    Curves(CurvesArgs),
    /// Untrimmed, watertight bicubic B-spline patches of an open shell (CAD faces or a
    /// triangle mesh) by Ricci flow; this version: disks whose boundary corners need no
    /// interior cone, and annuli with corner-free loops (one patch closing along its seam).
    /// See docs/spline.md.
    #[command(
        after_help = "Examples:\n  quadrille spline plate.step -o plate.step\n  quadrille spline part.step --faces 3 -o face3.iges --json\n  quadrille spline shell.stl -o shell.json --segments 4 --refine 2 --interior fit"
    )]
    Spline(SplineArgs),
}

/// How `quadrille spline` makes patch interiors.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum InteriorArg {
    /// The exact B-spline Coons patch of the four boundary curves (the paper).
    Coons,
    /// Least squares on the shell, boundary curves fixed (Coons where it would fold).
    Fit,
}

/// Arguments of `quadrille spline`.
#[derive(Args, Debug)]
pub struct SplineArgs {
    /// Shell: CAD (.step, .stp, .iges, .igs, .brep, .brp) or triangle mesh (.stl, .obj, .ply, .msh).
    input: PathBuf,
    #[command(flatten)]
    import: ImportArgs,
    /// Output: .step/.stp (one B-spline face per patch, sewn), .iges/.igs (type 128),
    /// .json (the multipatch) or .vtu (Bézier quadrilaterals).
    #[arg(short, long)]
    output: PathBuf,
    /// The faces that make the shell, 1-based (default: all).
    #[arg(long, value_delimiter = ',')]
    faces: Option<Vec<usize>>,
    /// Triangle edge length of the shell (default: the model's diagonal / 72).
    #[arg(long)]
    triangle_size: Option<f64>,
    /// Uniform spans per arc: a number, or auto (the smallest of 1, 2, 3, 4, 6, 8, 12, 16,
    /// 24, 32 meeting --tolerance).
    #[arg(long, default_value = "auto")]
    segments: String,
    /// Max distance of the shell's vertices to the patches (default: 0.1 % of the diagonal).
    #[arg(long)]
    tolerance: Option<f64>,
    /// Boehm refinement: every span split into this many.
    #[arg(long, default_value_t = 1)]
    refine: usize,
    /// Patch interiors.
    #[arg(long, value_enum, default_value_t = InteriorArg::Fit)]
    interior: InteriorArg,
    /// Write a picture of the patches with the layout drawn over them.
    #[arg(long, value_name = "PIC.png")]
    png: Option<PathBuf>,
    /// Cones from a file (lines `x y z index`, `#` comments; each point snapped to the
    /// nearest shell vertex) instead of the cross-field proposal.
    #[arg(long, value_name = "FILE")]
    cones: Option<PathBuf>,
    /// Write the cones (the proposal, or --cones) in the --cones format, for hand edits.
    #[arg(long, value_name = "FILE")]
    cones_out: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
    /// Print the time of each stage.
    #[arg(long)]
    timings: bool,
    /// Print nothing but errors.
    #[arg(long)]
    quiet: bool,
}

/// Arguments of `quadrille curves`.
#[derive(Args, Debug)]
pub struct CurvesArgs {
    /// Curve network: .json or .obj (docs/curve-networks.md), or a CAD model (.step, .stp,
    /// .iges, .igs, .brep, .brp) whose faces' boundary loops become the cycles.
    network: PathBuf,
    /// Output mesh: .msh (MSH 4.1), .vtu or .obj (not needed with --check).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Target edge length, in model units.
    #[arg(long, conflicts_with = "size_factor")]
    size: Option<f64>,
    /// Multiplier of the default edge length (1/24 of the network's bounding-box diagonal).
    #[arg(long)]
    size_factor: Option<f64>,
    /// CAD input: the faces whose boundaries to mesh, 1-based (default: all).
    #[arg(long, value_delimiter = ',')]
    faces: Option<Vec<usize>>,
    /// Write a PNG picture of the mesh, the coarse layout drawn over it.
    #[arg(long, value_name = "PIC.png")]
    png: Option<PathBuf>,
    /// Write the coarse layout (one quad per patch) as OBJ.
    #[arg(long, value_name = "L.obj")]
    layout: Option<PathBuf>,
    /// Save the network that was read as JSON.
    #[arg(long, value_name = "F.json")]
    write_network: Option<PathBuf>,
    /// Validate the network only (with -o: validate, then mesh).
    #[arg(long)]
    check: bool,
    /// Mesh the valid cycles and list the others instead of failing.
    #[arg(long)]
    skip_bad: bool,
    /// Skip the network stage (T-junctions, intervals shared across cycles): each cycle sampled on its own, as a comparison
    #[arg(long)]
    no_network: bool,
    /// Refinement goes on while the average pair cost drops by this factor (paper: 1.25).
    #[arg(long)]
    drop: Option<f64>,
    /// Pairs cheaper than this are dominant and steer their neighbours (paper: 0.15).
    #[arg(long)]
    dom: Option<f64>,
    /// Print the report as JSON (per cycle: segments, pairs, costs, patches, valences, time).
    #[arg(long)]
    json: bool,
    /// Print the time of each stage.
    #[arg(long)]
    timings: bool,
    /// Worker threads (default: all cores); the output is the same for any count.
    #[arg(long)]
    threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(long)]
    quiet: bool,
}

/// Options of the triangle-mesh import (STL, OBJ, PLY, MSH models).
#[derive(Args, Debug, Clone)]
pub struct ImportArgs {
    /// Triangle-mesh input: dihedral angle (degrees) above which an edge is a
    /// feature curve edge.
    #[arg(long, default_value_t = trimesh::DEFAULT_FEATURE_ANGLE)]
    feature_angle: f64,
    /// Triangle-mesh input: a file of extra feature edges, one pair of
    /// 1-based vertex numbers per line.
    #[arg(long, value_name = "FILE")]
    feature_edges: Option<PathBuf>,
}

/// Arguments of `quadrille info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Model: CAD (.step, .stp, .iges, .igs, .brep, .brp) or triangle mesh (.stl, .obj, .ply, .msh).
    model: PathBuf,
    #[command(flatten)]
    import: ImportArgs,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
}

/// Arguments of `quadrille mesh`.
#[derive(Args, Debug)]
pub struct MeshArgs {
    /// Model: CAD (.step, .stp, .iges, .igs, .brep, .brp) or triangle mesh (.stl, .obj, .ply, .msh).
    model: PathBuf,
    #[command(flatten)]
    import: ImportArgs,
    /// Output mesh: .msh (MSH 4.1), .vtu (VTK) or .obj.
    #[arg(short, long)]
    output: PathBuf,
    /// Target edge length, in model units.
    #[arg(long, conflicts_with = "size_factor")]
    size: Option<f64>,
    /// Multiplier of the default edge length (1/24 of the bounding-box diagonal).
    #[arg(long)]
    size_factor: Option<f64>,
    /// Curved faces: quads per full turn of the surface normal (a 90° fillet
    /// gets a quarter of them across), kept within half to twice the target
    /// edge length; 0 turns it off. Not used by the baseline and regular methods.
    #[arg(long, default_value_t = quadrille::DEFAULT_QUADS_PER_TURN, value_name = "N")]
    quads_per_turn: f64,
    /// Worker threads (default: all cores). The output is the same for any count.
    #[arg(long)]
    threads: Option<usize>,
    /// Also draw the mesh to this PNG picture.
    #[arg(long)]
    png: Option<PathBuf>,
    /// Write binary MSH instead of ASCII.
    #[arg(long)]
    binary: bool,
    /// MSH: also write the parametric coordinates of curve and face nodes
    /// (as Gmsh's `Mesh.SaveParametric`). Off by default: meshio cannot read
    /// them; entities and node classification are written either way.
    #[arg(long)]
    parametric: bool,
    /// No progress bar and no summary.
    #[arg(short, long)]
    quiet: bool,
    /// Meshing method (see the list below).
    #[arg(long, value_enum, default_value_t = Method::QuasiStructured)]
    method: Method,
    /// quasi-structured: do not mesh simple faces directly by a pattern.
    #[arg(long)]
    no_patterns: bool,
    /// quasi-structured: do not replace very irregular vertices (valence 2 or ≥ 6) by disk quadrangulations.
    #[arg(long)]
    no_defects: bool,
    /// quasi-structured: no cavity remeshing around unneeded irregular vertices.
    #[arg(long)]
    no_cavities: bool,
    /// quasi-structured: no last pass of the regular method's swaps, collapses and splits on what the cavities left.
    #[arg(long)]
    no_regular_pass: bool,
    /// Print the time of each stage on stderr (a table, then one `timings:` JSON
    /// line), with the estimated and the made quad counts.
    #[arg(long)]
    timings: bool,
    /// Refuse to mesh when the quad count estimated before meshing is above
    /// N (the message says the memory it would take and a size that fits);
    /// 0 lifts the limit.
    #[arg(long, value_name = "N", default_value_t = quadrille::DEFAULT_MAX_QUADS)]
    max_quads: u64,
    #[command(flatten)]
    coarse: CoarseArgs,
}

/// Options of `--method coarse`.
#[derive(Args, Debug)]
pub struct CoarseArgs {
    /// coarse: Lagrange order of the curved quads, 1–10 (1 writes the block layout alone) [default: 5].
    #[arg(long, value_name = "N")]
    order: Option<usize>,
    /// coarse: cone half-angle (degrees, in (0, 90)) within which traces align irregular vertices [default: 45].
    #[arg(long, value_name = "DEG")]
    alpha: Option<f64>,
    /// coarse: time limit of the integer program, seconds (0: keep the input layout) [default: 60].
    #[arg(long, value_name = "S")]
    ilp_time_limit: Option<f64>,
    /// coarse: start from this all-quad MSH mesh of the same model instead of meshing it.
    #[arg(long, value_name = "F.msh")]
    from_mesh: Option<PathBuf>,
    /// coarse: also write the block layout (straight blocks): .msh, .vtu or .obj.
    #[arg(long, value_name = "FILE")]
    layout: Option<PathBuf>,
    /// coarse: also write the fine block-structured quad mesh: .msh or .vtu.
    #[arg(long, value_name = "FILE")]
    fine: Option<PathBuf>,
    /// coarse: print the run's figures as JSON on stdout.
    #[arg(long)]
    json: bool,
}

impl CoarseArgs {
    /// The options given on the command line, by name (to refuse them with
    /// another method).
    fn given(&self) -> Vec<&'static str> {
        let mut v = Vec::new();
        for (on, name) in [
            (self.order.is_some(), "--order"),
            (self.alpha.is_some(), "--alpha"),
            (self.ilp_time_limit.is_some(), "--ilp-time-limit"),
            (self.from_mesh.is_some(), "--from-mesh"),
            (self.layout.is_some(), "--layout"),
            (self.fine.is_some(), "--fine"),
            (self.json, "--json"),
        ] {
            if on {
                v.push(name);
            }
        }
        v
    }
}

/// The meshing methods of `quadrille mesh`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The default: cross field and size map; simple faces meshed by a pattern;
    /// the others by frontal points along the cross field, recombination and
    /// subdivision; then very irregular vertices and cavities remeshed
    /// (--no-patterns, --no-defects, --no-cavities, --no-regular-pass switch
    /// steps off).
    QuasiStructured,
    /// Frontal points along the cross field, recombination and subdivision
    /// (paper §5): the quasi-structured method without its topology steps
    /// (no patterns, defect removal, cavity remeshing or regular pass), its
    /// front keeping the spacing of the curves along each direction (two ways
    /// tried per face, the more regular kept).
    Unstructured,
    /// Triangulate each face in uv and split every triangle into three quads
    /// (always valid, about half the vertices irregular).
    Baseline,
    /// The baseline, then swaps, collapses and splits towards regular vertices.
    Regular,
    /// A coarse block layout by an integer program over the default method's
    /// quads, then one curved Lagrange quad of order --order per block
    /// (--alpha, --ilp-time-limit, --from-mesh, --layout, --fine, --json).
    Coarse,
}

/// Arguments of `quadrille stats`.
#[derive(Args, Debug)]
pub struct StatsArgs {
    /// Mesh file (MSH 4.1 or 2.2, ASCII or binary).
    mesh: PathBuf,
    /// The CAD model the mesh was made from: quality uses the CAD normals and
    /// the distance of the nodes to the CAD is reported.
    #[arg(long)]
    cad: Option<PathBuf>,
    /// How a triangle-mesh `--cad` model is read (the same options as `mesh`).
    #[command(flatten)]
    import: ImportArgs,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
}

/// Arguments of `quadrille render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Mesh file (MSH 4.1 or 2.2).
    mesh: PathBuf,
    /// Output picture (.png).
    #[arg(short, long)]
    output: PathBuf,
    /// Colour quads by SICN (red = poor, green = good).
    #[arg(long)]
    sicn: bool,
    /// CAD model, for SICN with CAD normals.
    #[arg(long)]
    cad: Option<PathBuf>,
    /// How a triangle-mesh `--cad` model is read (the same options as `mesh`).
    #[command(flatten)]
    import: ImportArgs,
    /// Picture width in pixels.
    #[arg(long, default_value_t = 1600)]
    width: u32,
    /// Picture height in pixels.
    #[arg(long, default_value_t = 1200)]
    height: u32,
    /// Viewing direction (from the eye towards the model), as x,y,z.
    #[arg(long, value_delimiter = ',', num_args = 3, allow_hyphen_values = true)]
    view: Option<Vec<f64>>,
    /// Do not mark irregular vertices.
    #[arg(long)]
    no_irregular: bool,
}

/// Arguments of `quadrille field`.
#[derive(Args, Debug)]
pub struct FieldArgs {
    /// Model: CAD (.step, .stp, .iges, .igs, .brep, .brp) or triangle mesh (.stl, .obj, .ply, .msh).
    model: PathBuf,
    #[command(flatten)]
    import: ImportArgs,
    /// Output field file (.vtu). Optional: `--json` alone prints the report
    /// and writes nothing (one of -o, --png, --size-png, --json is needed).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also draw the field to this PNG picture: shaded triangulation, cross
    /// glyphs, singularities coloured by index.
    #[arg(long)]
    png: Option<PathBuf>,
    /// Also draw the size map to this PNG picture (red: smallest sizes, green:
    /// largest), with the singularities.
    #[arg(long)]
    size_png: Option<PathBuf>,
    /// Print per-face singularities, corner indices and the Eq. (2) check as JSON on stdout.
    #[arg(long)]
    json: bool,
    /// Target quad edge length, in model units (the background triangles are finer).
    #[arg(long, conflicts_with = "size_factor")]
    size: Option<f64>,
    /// Multiplier of the default quad edge length (1/24 of the bounding-box diagonal).
    #[arg(long)]
    size_factor: Option<f64>,
    /// Largest growth of the size map per unit of distance (Eq. 10 of the paper).
    #[arg(long, default_value_t = quadrille::field::DEFAULT_GRADIENT)]
    size_gradient: f64,
    /// Do not shrink sizes at small CAD features (short curves, curves close to each other).
    #[arg(long)]
    no_small_features: bool,
    /// Sizes are never below this (model units).
    #[arg(long)]
    min_size: Option<f64>,
    /// Sizes are never above this (model units).
    #[arg(long)]
    max_size: Option<f64>,
    /// Curved faces: quads per full turn of the surface normal, as in
    /// `quadrille mesh`; 0 turns it off.
    #[arg(long, default_value_t = quadrille::DEFAULT_QUADS_PER_TURN, value_name = "N")]
    quads_per_turn: f64,
    /// A size on one entity, `KIND:ID=SIZE` with KIND `corner`, `curve` or
    /// `face` and ID 1-based as in `quadrille info` (repeatable), e.g. `curve:3=0.05`.
    #[arg(long = "entity-size", value_name = "KIND:ID=SIZE", value_parser = parse_entity_size)]
    entity_sizes: Vec<(quadrille::field::Entity, f64)>,
    /// No progress bar and no summary.
    #[arg(short, long)]
    quiet: bool,
}

/// Parses `KIND:ID=SIZE` (see `--entity-size`).
fn parse_entity_size(text: &str) -> Result<(quadrille::field::Entity, f64), String> {
    use quadrille::field::Entity;
    let bad = || format!("`{text}` is not KIND:ID=SIZE (e.g. curve:3=0.05)");
    let (entity, size) = text.split_once('=').ok_or_else(bad)?;
    let (kind, id) = entity.split_once(':').ok_or_else(bad)?;
    let id: u32 = id.trim().parse().map_err(|_| bad())?;
    if id == 0 {
        return Err(format!("`{text}`: entity numbers start at 1"));
    }
    let size: f64 = size.trim().parse().map_err(|_| bad())?;
    if !(size.is_finite() && size > 0.0) {
        return Err(format!("`{text}`: the size must be a positive number"));
    }
    let entity = match kind.trim() {
        "corner" => Entity::Corner(geometry::CornerId(id - 1)),
        "curve" => Entity::Curve(geometry::CurveId(id - 1)),
        "face" => Entity::Face(geometry::FaceId(id - 1)),
        other => {
            return Err(format!(
                "`{text}`: unknown entity kind `{other}` (corner, curve or face)"
            ))
        }
    };
    Ok((entity, size))
}

/// The mesh size of `--size H` / `--size-factor F` (H wins; the default size when neither is given).
fn size_arg(size: Option<f64>, factor: Option<f64>) -> quadrille::Size {
    match (size, factor) {
        (Some(h), _) => quadrille::Size::Absolute(h),
        (None, Some(f)) => quadrille::Size::Factor(f),
        (None, None) => quadrille::Size::Factor(1.0),
    }
}

/// The error and its causes on one line, `a: b: c`, leaving out a cause whose
/// text the message already holds (many library errors print their source).
fn error_chain(e: &anyhow::Error) -> String {
    let mut msg = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !msg.contains(&c) {
            msg.push_str(": ");
            msg.push_str(&c);
        }
    }
    msg
}

/// Restores the default SIGPIPE action, so `quadrille info model.step | head`
/// ends quietly when the reader closes the pipe instead of panicking in `println!`.
fn quiet_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: setting a signal disposition to SIG_DFL at start-up, before any thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// The environment variable holding the library's log filter, as `RUST_LOG`
/// (for example `quadrille=debug`: each stage's rounds and the quads it
/// could not fix, on stderr). Unset, nothing is logged.
const LOG_VARIABLE: &str = "QUADRILLE_LOG";

/// Sends the library's `tracing` events to stderr when [`LOG_VARIABLE`]
/// holds a filter. The only place the program reads an environment variable
/// of its own.
fn set_up_logging() {
    let Ok(filter) = std::env::var(LOG_VARIABLE) else {
        return;
    };
    match tracing_subscriber::EnvFilter::try_new(&filter) {
        Ok(f) => {
            tracing_subscriber::fmt()
                .with_env_filter(f)
                .with_writer(std::io::stderr)
                .without_time()
                .init();
        }
        Err(e) => {
            eprintln!("warning: {LOG_VARIABLE}={filter:?} is not a log filter ({e}); logging off")
        }
    }
}

fn main() -> ExitCode {
    quiet_on_closed_pipe();
    set_up_logging();
    let cli = Cli::parse();
    let import = match &cli.command {
        Command::Info(a) => Some(&a.import),
        Command::Mesh(a) => Some(&a.import),
        Command::Field(a) => Some(&a.import),
        Command::Stats(a) => Some(&a.import),
        Command::Render(a) => Some(&a.import),
        Command::Curves(_) => None,
        Command::Spline(a) => Some(&a.import),
    };
    if let Some(Err(e)) = import.map(files::set_trimesh_options) {
        eprintln!("error: {}", error_chain(&e));
        return ExitCode::FAILURE;
    }
    let result = match cli.command {
        Command::Info(a) => cmd_info::run(&a),
        Command::Mesh(a) => cmd_mesh::run(&a),
        Command::Stats(a) => cmd_stats::run(&a),
        Command::Render(a) => cmd_render::run(&a),
        Command::Field(a) => cmd_field::run(&a),
        Command::Curves(a) => cmd_curves::run(&a),
        Command::Spline(a) => cmd_spline::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", error_chain(&e));
            ExitCode::FAILURE
        }
    }
}
