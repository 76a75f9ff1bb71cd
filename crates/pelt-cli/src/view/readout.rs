//! The frame-time readout in the window title: the median time of the recent frames' render
//! calls (until the GPU finished them, without the wait for presentation), the frame rate that
//! time allows, what was drawn and on which adapter; refreshed about twice a second so it can be
//! read.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use pelt_render::FrameInfo;

/// Frames the median is taken over.
const RECENT: usize = 31;
/// Shortest time between two title updates.
pub const REFRESH: Duration = Duration::from_millis(500);

/// Render times of the recent frames.
#[derive(Debug, Default)]
pub struct FrameTimes {
    recent: VecDeque<f64>,
}

impl FrameTimes {
    pub fn push(&mut self, seconds: f64) {
        if self.recent.len() == RECENT {
            self.recent.pop_front();
        }
        self.recent.push_back(seconds);
    }

    /// Median of the recent times, seconds (the mean of the middle two for an even count).
    pub fn median(&self) -> Option<f64> {
        let mut sorted: Vec<f64> = self.recent.iter().copied().collect();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        match n {
            0 => None,
            _ if n % 2 == 1 => Some(sorted[n / 2]),
            _ => Some(0.5 * (sorted[n / 2 - 1] + sorted[n / 2])),
        }
    }
}

/// What the title shows besides the times.
pub struct Shown<'a> {
    pub object: &'a str,
    pub info: &'a FrameInfo,
    pub lod: bool,
    pub fins: bool,
    pub marched: bool,
    pub model: &'a str,
    pub adapter: &'a str,
}

/// The window title.
pub fn title(median: Option<f64>, shown: &Shown<'_>) -> String {
    let time = match median {
        Some(s) if s > 0.0 => format!("{:.2} ms ({:.0} fps)", s * 1e3, 1.0 / s),
        _ => "– ms".to_string(),
    };
    let lod = if shown.lod {
        format!("LOD {}", shown.info.level)
    } else {
        "LOD off".into()
    };
    let fins = if shown.fins { "fins" } else { "no fins" };
    let shells = if shown.marched { "shells marched" } else { "shells" };
    format!(
        "pelt view: {} | {time} | {} {shells} | {lod} | {fins} | {} triangles | {} | {}",
        shown.object, shown.info.shells, shown.info.triangles, shown.model, shown.adapter
    )
}

/// When the title may change next.
#[derive(Debug)]
pub struct Refresh {
    last: Option<Instant>,
}

impl Refresh {
    pub fn new() -> Self {
        Refresh { last: None }
    }

    /// `None` when the title may change now (and records that it does), else when it may.
    pub fn due(&mut self, now: Instant) -> Option<Instant> {
        match self.last {
            Some(last) if now < last + REFRESH => Some(last + REFRESH),
            _ => {
                self.last = Some(now);
                None
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info() -> FrameInfo {
        FrameInfo {
            shells: 12,
            level: 2,
            blend: 0.0,
            target_shells: 12.0,
            radius_pixels: None,
            fur_pixels: None,
            mesh_level: 0,
            triangles: 1000,
        }
    }

    #[test]
    fn the_median_is_of_the_recent_frames_only() {
        let mut times = FrameTimes::default();
        assert_eq!(times.median(), None);
        for s in [5.0, 1.0, 3.0] {
            times.push(s);
        }
        assert_eq!(times.median(), Some(3.0));
        times.push(2.0);
        assert_eq!(times.median(), Some(2.5));
        // A long run of 1s pushes the early frames out.
        for _ in 0..RECENT {
            times.push(1.0);
        }
        assert_eq!(times.median(), Some(1.0));
    }

    #[test]
    fn the_title_shows_time_rate_shells_lod_triangles_and_adapter() {
        let info = info();
        let shown = Shown {
            object: "Suzanne",
            info: &info,
            lod: true,
            fins: false,
            marched: false,
            model: "PRT",
            adapter: "llvmpipe",
        };
        let t = title(Some(0.004), &shown);
        for part in [
            "Suzanne",
            "4.00 ms",
            "(250 fps)",
            "12 shells",
            "LOD 2",
            "no fins",
            "1000 triangles",
            "PRT",
            "llvmpipe",
        ] {
            assert!(t.contains(part), "{part:?} missing from {t:?}");
        }
        let t = title(None, &Shown { lod: false, ..shown });
        assert!(t.contains("– ms") && t.contains("LOD off"), "{t}");
    }

    #[test]
    fn the_title_changes_at_most_twice_a_second() {
        let mut refresh = Refresh::new();
        let start = Instant::now();
        assert_eq!(refresh.due(start), None);
        assert_eq!(refresh.due(start + REFRESH / 2), Some(start + REFRESH));
        assert_eq!(refresh.due(start + REFRESH), None);
    }
}
