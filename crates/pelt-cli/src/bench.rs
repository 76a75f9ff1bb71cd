//! `pelt bench`: runs the benchmark cases and prints a table, optionally writing JSON.

use std::path::PathBuf;

use clap::Args;
use pelt_core::heap::TrackingAllocator;

use crate::cases::{self, BenchOptions};

#[derive(Args)]
pub struct BenchArgs {
    /// Smaller sizes and fewer repetitions: finishes in under a minute.
    #[arg(long)]
    quick: bool,
    /// Run only the cases whose name starts with this prefix.
    #[arg(long, value_name = "PREFIX")]
    only: Option<String>,
    /// Write the image cases' pictures (reference | preview | FLIP) into this folder.
    #[arg(long, value_name = "DIR")]
    pictures: Option<PathBuf>,
    /// Also write the results as JSON to this file.
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
}

pub fn run(args: BenchArgs) -> Result<(), String> {
    TrackingAllocator::enable();
    let options = BenchOptions {
        quick: args.quick,
        only: args.only,
        pictures: args.pictures,
    };
    let report = cases::run(&options).map_err(|e| e.to_string())?;
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
    if let Some(path) = args.json {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        std::fs::write(&path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}
