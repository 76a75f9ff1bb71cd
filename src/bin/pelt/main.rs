//! The `pelt` command line: `bench`, `bake`, `export` and `presets`, one file per subcommand. The
//! commands parse their arguments and call the library; errors print as one line and exit with
//! status 1.

mod bake;
mod bench;
mod export;
mod meshes;
mod presets;

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use pelt::bench::TrackingAllocator;

#[global_allocator]
static ALLOCATOR: TrackingAllocator = TrackingAllocator;

#[derive(Parser)]
#[command(name = "pelt", version, about = "Real-time fur on any mesh")]
struct Cli {
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
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Bench(args) => bench::run(args),
        Command::Bake(args) => bake::run(args),
        Command::Export(args) => export::run(args),
        Command::Presets(args) => presets::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("pelt: {message}");
            ExitCode::FAILURE
        }
    }
}
