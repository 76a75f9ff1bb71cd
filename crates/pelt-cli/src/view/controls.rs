//! What the viewer shows and how input changes it: the orbit camera and light (`orbit.rs`), the
//! shell count, fins, LOD and lighting model, and the keys and drags that change them.

use pelt_render::{KajiyaKay, LightModel, Lighting, Prt, RenderSettings, ShellMethod};
use winit::event::{ElementState, MouseButton, MouseScrollDelta};
use winit::keyboard::{Key, NamedKey};

use super::orbit::{Angles, Orbit};

/// Pixels of a touchpad scroll that count as one wheel line.
const PIXELS_PER_LINE: f64 = 40.0;
/// Pixels of drag one arrow key press turns the light by (15°).
const ARROW_PIXELS: f64 = 15.0 * std::f64::consts::PI / 180.0 / super::orbit::RADIANS_PER_PIXEL;
/// Linear background: a dark grey, opaque, so the window shows what a screenshot shows.
const BACKGROUND: [f32; 4] = [0.02, 0.02, 0.025, 1.0];

/// The key list printed at start.
pub const HELP: &str = "\
controls:
  left drag        orbit around the mesh
  wheel            zoom
  right drag, ←→↑↓ turn the light
  + / -            more / fewer shells (with LOD: the most LOD may draw)
  F                fins on / off
  M                shells instanced / marched per pixel (faster on a CPU, where it starts)
  V                virtual planes on / off (a bake with --planes)
  L                level of detail on / off
  K / P            Kajiya-Kay / PRT lighting
  R                reset the camera
  Esc, Q           quit";

/// One change asked for by the user.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    Orbit(f64, f64),
    Zoom(f64),
    Light(f64, f64),
    MoreShells,
    FewerShells,
    ToggleFins,
    ToggleMarched,
    TogglePlanes,
    ToggleLod,
    KajiyaKay,
    Prt,
    Reset,
    Quit,
}

/// What an action did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// The picture changed.
    Redraw,
    /// Nothing changed (the model asked for is already on).
    Unchanged,
    /// Nothing changed, and this says why.
    Refused(String),
    Quit,
}

/// The action of a pressed key.
pub fn key_action(key: &Key) -> Option<Action> {
    match key.as_ref() {
        Key::Named(NamedKey::Escape) => Some(Action::Quit),
        Key::Named(NamedKey::ArrowLeft) => Some(Action::Light(-ARROW_PIXELS, 0.0)),
        Key::Named(NamedKey::ArrowRight) => Some(Action::Light(ARROW_PIXELS, 0.0)),
        Key::Named(NamedKey::ArrowUp) => Some(Action::Light(0.0, -ARROW_PIXELS)),
        Key::Named(NamedKey::ArrowDown) => Some(Action::Light(0.0, ARROW_PIXELS)),
        Key::Character(text) => match text.to_ascii_lowercase().as_str() {
            // `=` is `+` without shift on most layouts.
            "+" | "=" => Some(Action::MoreShells),
            "-" | "_" => Some(Action::FewerShells),
            "f" => Some(Action::ToggleFins),
            "m" => Some(Action::ToggleMarched),
            "v" => Some(Action::TogglePlanes),
            "l" => Some(Action::ToggleLod),
            "k" => Some(Action::KajiyaKay),
            "p" => Some(Action::Prt),
            "r" => Some(Action::Reset),
            "q" => Some(Action::Quit),
            _ => None,
        },
        _ => None,
    }
}

/// Wheel lines of a scroll (positive: toward the mesh).
pub fn wheel_lines(delta: MouseScrollDelta) -> f64 {
    match delta {
        MouseScrollDelta::LineDelta(_, y) => f64::from(y),
        MouseScrollDelta::PixelDelta(p) => p.y / PIXELS_PER_LINE,
    }
}

/// Which button drags, and where the cursor was last.
#[derive(Debug, Default)]
pub struct Drag {
    button: Option<MouseButton>,
    last: Option<(f64, f64)>,
}

impl Drag {
    pub fn button(&mut self, button: MouseButton, state: ElementState) {
        match state {
            ElementState::Pressed if matches!(button, MouseButton::Left | MouseButton::Right) => {
                self.button = Some(button);
            }
            ElementState::Released if self.button == Some(button) => self.button = None,
            _ => {}
        }
    }

    /// The action of moving the cursor to `(x, y)`.
    pub fn moved(&mut self, x: f64, y: f64) -> Option<Action> {
        let last = self.last.replace((x, y))?;
        let (dx, dy) = (x - last.0, y - last.1);
        match self.button? {
            MouseButton::Left => Some(Action::Orbit(dx, dy)),
            _ => Some(Action::Light(dx, dy)),
        }
    }
}

/// Everything the user controls.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewState {
    pub orbit: Orbit,
    pub light: Angles,
    /// Shells above the skin (with LOD: the most it may draw).
    pub shells: u32,
    /// The volume's layers above the skin.
    pub max_shells: u32,
    pub fins: bool,
    /// Shells marched per pixel instead of instanced.
    pub marched: bool,
    pub lod: bool,
    pub prt: bool,
    /// Whether the scene has transfer textures (PRT possible).
    pub has_transfer: bool,
    /// Fur traced through the virtual planes instead of the shells.
    pub planes: bool,
    /// Whether the scene has the planes' slices.
    pub has_planes: bool,
}

impl ViewState {
    /// All shells, fins on, no LOD, Kajiya–Kay, for a volume of `layers` layers (the skin
    /// included).
    pub fn new(layers: u32, has_transfer: bool, has_planes: bool) -> Self {
        let max_shells = layers.saturating_sub(1);
        ViewState {
            orbit: Orbit::default(),
            light: Angles::of(Lighting::default().direction),
            shells: max_shells,
            max_shells,
            fins: true,
            marched: false,
            lod: false,
            prt: false,
            has_transfer,
            planes: false,
            has_planes,
        }
    }

    pub fn apply(&mut self, action: Action) -> Outcome {
        match action {
            Action::Orbit(dx, dy) => self.orbit.rotate(dx, dy),
            Action::Zoom(lines) => self.orbit.zoom_by(lines),
            Action::Light(dx, dy) => self.light.rotate(dx, dy),
            Action::MoreShells | Action::FewerShells => {
                let fewest = self.max_shells.min(1);
                let shells = match action {
                    Action::MoreShells => self.shells.saturating_add(1),
                    _ => self.shells.saturating_sub(1),
                }
                .clamp(fewest, self.max_shells);
                if shells == self.shells {
                    return Outcome::Refused(format!(
                        "shells stay in [{fewest}, {}] (the volume's layers above the skin)",
                        self.max_shells
                    ));
                }
                self.shells = shells;
            }
            Action::ToggleFins => self.fins = !self.fins,
            Action::ToggleMarched => self.marched = !self.marched,
            Action::TogglePlanes if !self.has_planes => {
                return Outcome::Refused(
                    "the virtual planes need their slices; bake with --planes 32".into(),
                );
            }
            Action::TogglePlanes => self.planes = !self.planes,
            Action::ToggleLod => self.lod = !self.lod,
            Action::KajiyaKay if self.prt => self.prt = false,
            Action::Prt if !self.has_transfer => {
                return Outcome::Refused(
                    "PRT needs transfer textures; this asset was baked with --no-transfer".into(),
                );
            }
            Action::Prt if !self.prt => self.prt = true,
            Action::KajiyaKay | Action::Prt => return Outcome::Unchanged,
            Action::Reset => self.orbit = Orbit::default(),
            Action::Quit => return Outcome::Quit,
        }
        Outcome::Redraw
    }

    /// The render settings of the view (the fur depth is the scene's).
    pub fn settings(&self) -> RenderSettings {
        let base = RenderSettings {
            fins: self.fins,
            shell_method: match (self.planes, self.marched) {
                (true, _) => ShellMethod::VirtualPlanes,
                (false, true) => ShellMethod::Marched,
                (false, false) => ShellMethod::Instanced,
            },
            background: BACKGROUND,
            ..RenderSettings::default()
        };
        if self.lod {
            RenderSettings {
                shell_count: None,
                lod: true,
                max_shells: self.shells,
                min_shells: base.min_shells.min(self.shells),
                ..base
            }
        } else {
            RenderSettings {
                shell_count: Some(self.shells),
                ..base
            }
        }
    }

    pub fn lighting(&self) -> Lighting {
        Lighting {
            direction: self.light.direction(),
            model: if self.prt {
                LightModel::Prt(Prt::default())
            } else {
                LightModel::KajiyaKay(KajiyaKay::default())
            },
            ..Lighting::default()
        }
    }

    /// The lighting model's name.
    pub fn model_name(&self) -> &'static str {
        if self.prt { "PRT" } else { "Kajiya-Kay" }
    }
}

#[cfg(test)]
mod tests;
