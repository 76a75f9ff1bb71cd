//! `pelt presets`: the fur presets `pelt bake --preset` accepts.

use clap::Args;
use pelt_core::presets::presets;

#[derive(Args)]
pub struct PresetsArgs {
    /// Print every preset's values as JSON instead of a list.
    #[arg(long)]
    json: bool,
}

pub fn run(args: PresetsArgs) -> Result<(), String> {
    if args.json {
        let text = serde_json::to_string_pretty(presets()).map_err(|e| e.to_string())?;
        println!("{text}");
        return Ok(());
    }
    for preset in presets() {
        println!(
            "{:<14} {} (fur depth {}, tile {})",
            preset.name.to_ascii_lowercase(),
            preset.description,
            preset.fur_depth,
            preset.tile_size
        );
    }
    Ok(())
}
