//! The `pelt` command line. Subcommands grow with the pipeline; today: `bench`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use pelt::bench::{self, BenchOptions, TrackingAllocator};

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
    Bench {
        /// Smaller sizes and fewer repetitions: finishes in under a minute.
        #[arg(long)]
        quick: bool,
        /// Run only the cases whose name starts with this prefix.
        #[arg(long, value_name = "PREFIX")]
        only: Option<String>,
        /// Also write the results as JSON to this file.
        #[arg(long, value_name = "PATH")]
        json: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Bench { quick, only, json } => run_bench(BenchOptions { quick, only }, json),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("pelt: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run_bench(options: BenchOptions, json: Option<PathBuf>) -> Result<(), String> {
    TrackingAllocator::enable();
    let report = bench::run(&options).map_err(|e| e.to_string())?;
    println!("pelt {} bench, {} threads", report.pelt, report.threads);
    println!(
        "{:<28} {:>12} {:>12} {:>10}  size",
        "case", "seconds", "peak MiB", "error"
    );
    for case in &report.cases {
        let peak = case
            .peak_bytes
            .map_or("-".into(), |b| format!("{:.1}", b as f64 / 1048576.0));
        let error = case.error.map_or("-".into(), |e| format!("{e:.2e}"));
        println!(
            "{:<28} {:>12.6} {:>12} {:>10}  {}",
            case.name, case.seconds, peak, error, case.size
        );
    }
    if let Some(path) = json {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        std::fs::write(&path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}
