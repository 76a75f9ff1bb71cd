//! Bakes one hair volume with per-stage timings, for profiling the bake outside `pelt bench`
//! (e.g. under `valgrind --tool=callgrind --toggle-collect='*bake_strands*'`).
//!
//! Usage: `volume_bake [resolution] [layers] [strands] [stages] [coverage] [vertical_filter]`,
//! defaults 512 32 50000 all exact 0; `stages` is `all` (LOD chain and mipmaps), `shells`
//! (neither) or `lod` (LOD chain only).
//! The hair widths scale with the resolution as in the bench, so hairs stay about a texel wide.

use std::time::Instant;

use pelt::hair::{HairParams, grow_strands};
use pelt::volume::{VolumeParams, bake_strands};

fn main() -> pelt::error::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (resolution, layers, density) = (arg(0, 512), arg(1, 32), arg(2, 50_000));
    let stages = args.get(3).map_or("all", String::as_str);
    let coverage = args.get(4).map_or("exact", String::as_str).parse()?;
    let vertical_filter = args.get(5).and_then(|a| a.parse().ok()).unwrap_or(0.0);
    let scale = 128.0 / resolution as f64;
    let defaults = HairParams::default();
    let mut hair = HairParams {
        density: density as u32,
        ..defaults.clone()
    };
    hair.undercoat.width = defaults.undercoat.width.map(|w| w * scale);
    hair.overcoat.width = defaults.overcoat.width.map(|w| w * scale);
    let strands = grow_strands(&hair)?;
    let params = VolumeParams {
        resolution,
        layers,
        lod: stages != "shells",
        mipmaps: stages == "all",
        coverage,
        vertical_filter,
        ..VolumeParams::default()
    };
    let (start, cpu_start) = (Instant::now(), cpu_seconds());
    let volume = bake_strands(&strands, &params, None)?;
    let seconds = start.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu_start;
    // A checksum of every output, so that two builds can be compared byte for byte.
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |bytes: &[u8]| {
        let mut words = bytes.chunks_exact(8);
        for w in &mut words {
            let mut word = [0u8; 8];
            word.copy_from_slice(w);
            hash = (hash ^ u64::from_le_bytes(word)).wrapping_mul(0x100_0000_01b3);
        }
        for &b in words.remainder() {
            hash = (hash ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
    };
    eat(&volume.shells);
    eat(&volume.tangents);
    volume.coverage.iter().for_each(|c| eat(&c.to_le_bytes()));
    eat(&volume.fin);
    volume.lod.iter().for_each(|l| eat(l));
    volume.mips.iter().for_each(|m| eat(m));
    let stats = &volume.stats;
    eat(&stats.tallest.to_le_bytes());
    stats.mean_coverage.iter().for_each(|m| eat(&m.to_le_bytes()));
    println!(
        "{resolution}x{resolution}x{} from {} strands ({stages}): {seconds:.3} s, cpu {cpu:.2} s, \
         checksum {hash:016x}",
        volume.layers,
        strands.len()
    );
    Ok(())
}

/// User and system time of the whole process so far (all threads), from `/proc/self/stat`, in
/// seconds assuming the usual 100 ticks per second; NaN where that file is missing.
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return f64::NAN;
    };
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let tick = |i: usize| {
        fields
            .get(i)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(f64::NAN)
    };
    (tick(11) + tick(12)) / 100.0
}
