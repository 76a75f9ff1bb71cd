//! `pelt view ASSET_DIR` (feature `viewer`): a window showing one object of a baked folder with
//! the real-time renderer (Lengyel et al. 2001, §2.3–§2.4: skin, fins, shells, LOD), an orbit
//! camera, a movable light, shell, fin, LOD and lighting toggles, and a frame-time readout in the
//! title. The folder is loaded by baking its `bake.json` again (the bake is deterministic).
//!
//! Files: `app.rs` (window and event loop), `controls.rs` (view state and input), `orbit.rs`
//! (camera and light angles), `readout.rs` (frame times and title).

mod app;
mod controls;
mod orbit;
mod readout;

use std::path::PathBuf;

use clap::Args;
use pelt_render::AdapterChoice;
use winit::event_loop::EventLoop;

use crate::bake;

#[derive(Args)]
pub struct ViewArgs {
    /// A folder written by `pelt bake` (it holds bake.json).
    pub asset_dir: PathBuf,
    /// Adapter: auto (a GPU when there is one, else the CPU), cpu or gpu.
    #[arg(long, value_name = "KIND", default_value = "auto", value_parser = parse_adapter)]
    pub adapter: AdapterChoice,
    /// Render N frames, then exit (for scripts and tests).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// Save the last frame as PNG (with --frames the N-th, else the one shown when quitting).
    #[arg(long, value_name = "FILE.png")]
    pub screenshot: Option<PathBuf>,
    /// Window size in pixels.
    #[arg(long, value_name = "WxH", default_value = "960x720", value_parser = parse_size)]
    pub size: Size,
    /// Object to show (default: the mesh file's first).
    #[arg(long, value_name = "NAME")]
    pub object: Option<String>,
}

/// A window size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

/// Largest window side accepted on the command line.
const MAX_SIDE: u32 = 16384;

fn parse_size(text: &str) -> Result<Size, String> {
    let bad = || format!("{text:?} is not a size WxH with sides in [1, {MAX_SIDE}], e.g. 960x720");
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let side = |s: &str| {
        s.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| (1..=MAX_SIDE).contains(v))
    };
    match (side(w), side(h)) {
        (Some(width), Some(height)) => Ok(Size { width, height }),
        _ => Err(bad()),
    }
}

fn parse_adapter(text: &str) -> Result<AdapterChoice, String> {
    match text {
        "auto" => Ok(AdapterChoice::PreferHardware),
        "cpu" => Ok(AdapterChoice::Cpu),
        "gpu" => Ok(AdapterChoice::Gpu),
        other => Err(format!("{other:?} is not auto, cpu or gpu")),
    }
}

pub fn run(args: ViewArgs) -> Result<(), String> {
    let record = bake::load_record(&args.asset_dir)?;
    let (params, objects) = bake::prepare(&record)?;
    let names = || {
        objects
            .iter()
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let (name, data) = match &args.object {
        None => objects.first(),
        Some(wanted) => objects.iter().find(|(n, _)| n == wanted),
    }
    .ok_or_else(|| match &args.object {
        Some(wanted) => format!(
            "no object {wanted:?} in {} (it has {})",
            record.mesh.display(),
            names()
        ),
        None => format!("{} has no objects", record.mesh.display()),
    })?;
    eprintln!(
        "pelt view: loading {name} (baking {} again)",
        record.mesh.display()
    );
    let asset = bake::bake_object(&record, &params, name, data)?;

    let event_loop = EventLoop::new().map_err(|e| format!("cannot open a window: {}", os_message(&e)))?;
    let mut app = app::App::new(app::Options {
        adapter: args.adapter,
        frames: args.frames,
        screenshot: args.screenshot,
        size: args.size,
        object: name.clone(),
        asset,
    });
    event_loop
        .run_app(&mut app)
        .map_err(|e| format!("the window's event loop failed: {}", os_message(&e)))?;
    app.finish()
}

/// A windowing error without the source location winit puts in front of OS errors
/// ("os error at src/…/mod.rs:765: …"), which means nothing to a user.
pub fn os_message(e: &impl std::fmt::Display) -> String {
    let text = e.to_string();
    match text
        .find(".rs:")
        .and_then(|i| text[i..].find(": ").map(|j| i + j + 2))
    {
        Some(start) if text.starts_with("os error at ") => text[start..].to_string(),
        _ => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_bad_ones_are_refused() {
        assert_eq!(
            parse_size("64x48"),
            Ok(Size {
                width: 64,
                height: 48
            })
        );
        assert_eq!(parse_size("8X8").map(|s| s.width), Ok(8));
        for bad in ["64", "0x10", "10x", "x", "-1x5", "99999x5", "axb"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn os_errors_lose_their_source_location() {
        let e = "os error at /a/winit/src/linux/mod.rs:788: Failed to open connection to X server";
        assert_eq!(os_message(&e), "Failed to open connection to X server");
        assert_eq!(os_message(&"plain: message"), "plain: message");
    }

    #[test]
    fn adapters_parse() {
        assert_eq!(parse_adapter("cpu"), Ok(AdapterChoice::Cpu));
        assert_eq!(parse_adapter("gpu"), Ok(AdapterChoice::Gpu));
        assert_eq!(parse_adapter("auto"), Ok(AdapterChoice::PreferHardware));
        assert!(parse_adapter("vulkan").is_err());
    }
}
