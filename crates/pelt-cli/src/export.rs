//! `pelt export ASSET_DIR`: writes a folder made by `pelt bake` again — in other formats or modes,
//! or into another folder. Pelt keeps no baked data besides the exported files, so the bake is
//! run again from the arguments recorded in `bake.json` (same mesh, same settings); the bake is
//! deterministic, so the textures come out identical.

use std::path::PathBuf;

use clap::Args;

use crate::bake;

#[derive(Args)]
pub struct ExportArgs {
    /// A folder written by `pelt bake` (it holds bake.json).
    pub asset_dir: PathBuf,
    /// Folder to write into (default: the asset folder itself).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// glTF files to write: geometry, engine or both (default: as recorded).
    #[arg(long, value_name = "MODE")]
    pub mode: Option<String>,
    /// Texture containers, comma-separated: png, ktx2, exr (default: as recorded).
    #[arg(long, value_name = "LIST")]
    pub formats: Option<String>,
    /// Leave the fins out of the geometry glTF.
    #[arg(long)]
    pub no_fins: bool,
}

pub fn run(args: ExportArgs) -> Result<(), String> {
    let mut recorded = bake::load_record(&args.asset_dir)?;
    recorded.out = args.out.unwrap_or(args.asset_dir);
    if let Some(mode) = args.mode {
        recorded.mode = mode;
    }
    if let Some(formats) = args.formats {
        recorded.formats = formats;
    }
    recorded.no_fins |= args.no_fins;
    bake::run(recorded)
}
