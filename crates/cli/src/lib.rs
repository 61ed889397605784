//! The `cvtmesh` command: mesh your own planar region with constrained CVT (or a peer
//! method), score meshes with the paper's 12 quality measures, and draw them.
//!
//! The command is a library so that the same command, with the same words and the same exit
//! codes, runs from the `cvtmesh` binary and from the Python package's `cvtmesh` entry point.
//!
//! ```
//! // `cvtmesh regions`: the built-in regions, one per line.
//! assert_eq!(cvtmesh_cli::run(["cvtmesh", "regions"]), 0);
//! // An unknown region is an error with a non-zero exit, not a panic.
//! assert_eq!(cvtmesh_cli::run(["cvtmesh", "regions", "no_such_region"]), 1);
//! ```
#![forbid(unsafe_code)]

/// `println!` for what a command prints on standard output; a reader that has gone
/// (`cvtmesh measure … | head -1`) ends the command quietly instead of panicking.
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::print_line(format_args!($($arg)*))
    };
}

mod commands;
mod inputs;

use clap::{Parser, Subcommand};
use std::ffi::OsString;

#[derive(Parser)]
#[command(
    name = "cvtmesh",
    version,
    about = "Triangular meshes of planar regions, uniform or graded by a size field, by constrained centroidal Voronoi tessellation"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Mesh a region (a file or a built-in name) and write the mesh; the format follows OUT's
    /// extension (.node/.ele Triangle, .msh Gmsh 4.1, .vtu VTK, .obj, .svg, .png).
    #[command(
        after_help = "Examples:\n  cvtmesh mesh circle --points 362 -o circle.msh\n  cvtmesh mesh lake --points 20000 --method ccvt2 -o lake.node\n  cvtmesh mesh coast.geojson --size 0.01 --corner-angle 30 -o coast.vtu\n  cvtmesh mesh square.poly --points 2000 --density '1 + 10*exp(-((x-0.5)^2+y^2)/0.01)' -o graded.png"
    )]
    Mesh(commands::MeshArgs),
    /// Print K, K̃ and the 12 quality measures of a mesh (Triangle .node+.ele, Gmsh .msh, .vtu, .obj).
    #[command(
        after_help = "Examples:\n  cvtmesh measure out.node --region circle\n  cvtmesh measure out.msh --region my_region.json --csv"
    )]
    Measure(commands::MeasureArgs),
    /// Raise the smallest angles of a mesh made by any tool: the vertices of its worst
    /// triangles move (boundary ones along the region's boundary, corners fixed), the triangles
    /// stay.
    ///
    /// No triangle or cell becomes worse in shape than the worst there was; unless the mesh is
    /// graded, no triangle becomes larger (in area or circumcircle) than the largest there was,
    /// and the cells' areas, reaches and shortest edges spread no wider (largest over
    /// smallest). A small triangle may get smaller within that spread.
    #[command(
        after_help = "Examples:\n  cvtmesh polish gmsh_mesh.msh --region lake -o lake_polished.msh\n  cvtmesh polish out.node --region my_region.json --below 35 -o polished.vtu"
    )]
    Polish(commands::PolishArgs),
    /// Draw a mesh or a region to PNG or SVG, optionally coloured by a per-triangle quality.
    #[command(
        after_help = "Examples:\n  cvtmesh show lake -o lake.png\n  cvtmesh show out.msh -o out.png\n  cvtmesh show out.msh --region lake --colour min-angle -o lake_mesh.svg"
    )]
    Show(commands::ShowArgs),
    /// List the built-in regions (the paper's ten), usable by name wherever a region is asked;
    /// with a region, its loops and boundary pieces with their markers (what --size-toward
    /// loop:I, piece:J and marker:M name).
    #[command(
        after_help = "Examples:\n  cvtmesh regions\n  cvtmesh regions square_hole\n  cvtmesh regions channel.poly --corner-angle 30"
    )]
    Regions(commands::RegionsArgs),
    /// Print the Voronoi dual of a mesh for finite volumes, as CSV: each edge's length and dual
    /// face (the two-point flux's transmissibility is face/length), or each vertex's control
    /// volume.
    #[command(
        after_help = "Examples:\n  cvtmesh dual lake.msh > faces.csv\n  cvtmesh dual lake.msh --volumes > volumes.csv"
    )]
    Dual(commands::DualArgs),
}

/// Runs the command line `args` (the program's name first, as in `std::env::args_os`) and
/// returns its exit code: 0 on success (and for `--help` and `--version`), 1 when the command
/// failed (the error is printed on standard error, one line), 2 when the words do not parse
/// (clap's message and usage on standard error).
pub fn run<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            // Help and version are "errors" that print on standard output and exit with 0.
            let _ = e.print();
            return e.exit_code();
        }
    };
    let result = match cli.command {
        Command::Mesh(a) => commands::mesh(a),
        Command::Measure(a) => commands::measure(a),
        Command::Polish(a) => commands::polish(a),
        Command::Show(a) => commands::show(a),
        Command::Regions(a) => commands::regions(a),
        Command::Dual(a) => commands::dual(a),
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            1
        }
    }
}

/// Write one line to standard output. Standard output is line-buffered, so a closed pipe
/// shows here: the command has nothing left to say to anyone and ends with success; any other
/// failure to write is an error.
fn print_line(args: std::fmt::Arguments) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.write_all(b"\n")) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: writing to standard output: {e}");
        std::process::exit(1);
    }
}

/// The error and its causes on one line. Many errors already quote their cause in their own
/// message; such a cause is not repeated.
fn one_line(e: &anyhow::Error) -> String {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !line.contains(&text) {
            line.push_str(": ");
            line.push_str(&text);
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use super::{one_line, Cli};
    use clap::CommandFactory;

    #[test]
    fn causes_are_shown_once() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let quoted = anyhow::Error::new(io).context("m.msh: cannot read: no such file");
        assert_eq!(one_line(&quoted), "m.msh: cannot read: no such file");
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let unquoted = anyhow::Error::new(io).context("writing m.msh");
        assert_eq!(one_line(&unquoted), "writing m.msh: no such file");
    }

    #[test]
    fn the_command_line_definition_is_consistent() {
        Cli::command().debug_assert();
    }
}
