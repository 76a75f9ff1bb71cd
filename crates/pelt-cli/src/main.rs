//! The `pelt` command line: `bench`, `bake`, `export`, `presets`, `reference` and, with the `viewer` feature,
//! `view`, one file (or folder) per subcommand. The commands parse their arguments and call the
//! library; errors print as one line and exit with status 1.

mod bake;
mod bench;
mod cases;
mod export;
mod meshes;
mod presets;
mod reference;
#[cfg(feature = "viewer")]
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use pelt_core::heap::TrackingAllocator;

#[global_allocator]
static ALLOCATOR: TrackingAllocator = TrackingAllocator;

#[derive(Parser)]
#[command(name = "pelt", version, about = "Real-time fur on any mesh")]
struct Cli {
    /// Most memory a stage may plan to use, e.g. 6G or 512M (default: PELT_MEMORY_LIMIT, else half
    /// of the physical memory); a bake above it stops before allocating and says what to lower.
    #[arg(long, global = true, value_name = "SIZE")]
    memory_limit: Option<String>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Time the pipeline's stages and print a table (median seconds, peak heap, error).
    Bench(bench::BenchArgs),
    /// Bake fur on a mesh (.obj, .glb, .gltf) and write textures, glTF and pelt.json.
    Bake(bake::BakeArgs),
    /// Write a baked folder again (other formats, modes or folder) from its recorded bake.
    Export(export::ExportArgs),
    /// List the fur presets.
    Presets(presets::PresetsArgs),
    /// Render a ground-truth image of a baked folder or a canonical scene (ray traced strands).
    Reference(reference::ReferenceArgs),
    /// Show a baked folder in a window: orbit, light, shells, fins, LOD, frame times.
    #[cfg(feature = "viewer")]
    View(view::ViewArgs),
    /// Show a baked folder in a window (this build lacks it: build with `--features viewer`).
    #[cfg(not(feature = "viewer"))]
    View {
        #[arg(trailing_var_arg = true, allow_hyphen_values = true, hide = true)]
        args: Vec<String>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = check_environment(cli.memory_limit.as_deref()) {
        eprintln!("pelt: {e}");
        return ExitCode::FAILURE;
    }
    let result = match cli.command {
        Command::Bench(args) => bench::run(args),
        Command::Bake(args) => bake::run(args),
        Command::Export(args) => export::run(args),
        Command::Presets(args) => presets::run(args),
        Command::Reference(args) => reference::run(args),
        #[cfg(feature = "viewer")]
        Command::View(args) => view::run(args),
        #[cfg(not(feature = "viewer"))]
        Command::View { .. } => Err(
            "`pelt view` needs a build with the viewer: cargo build --release -p pelt-cli --features viewer"
                .into(),
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("pelt: {message}");
            ExitCode::FAILURE
        }
    }
}

/// Refuses a malformed `PELT_THREADS` or memory limit before any work, and applies the limit.
fn check_environment(memory_limit: Option<&str>) -> pelt_core::Result<()> {
    pelt_core::threads::threads_from_env()?;
    pelt_core::memory::limit_from_env()?;
    if let Some(text) = memory_limit {
        pelt_core::memory::set_limit(Some(pelt_core::memory::parse_size("--memory-limit", text)?))?;
    }
    Ok(())
}
