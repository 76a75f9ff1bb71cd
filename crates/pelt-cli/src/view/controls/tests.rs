use super::*;

#[test]
fn keys_map_to_their_actions() {
    let ch = |s: &str| Key::Character(s.into());
    assert_eq!(key_action(&ch("+")), Some(Action::MoreShells));
    assert_eq!(key_action(&ch("=")), Some(Action::MoreShells));
    assert_eq!(key_action(&ch("-")), Some(Action::FewerShells));
    assert_eq!(key_action(&ch("F")), Some(Action::ToggleFins));
    assert_eq!(key_action(&ch("l")), Some(Action::ToggleLod));
    assert_eq!(key_action(&ch("V")), Some(Action::TogglePlanes));
    assert_eq!(key_action(&ch("k")), Some(Action::KajiyaKay));
    assert_eq!(key_action(&ch("P")), Some(Action::Prt));
    assert_eq!(key_action(&ch("r")), Some(Action::Reset));
    assert_eq!(key_action(&ch("q")), Some(Action::Quit));
    assert_eq!(key_action(&Key::Named(NamedKey::Escape)), Some(Action::Quit));
    assert_eq!(key_action(&ch("x")), None);
    match key_action(&Key::Named(NamedKey::ArrowLeft)) {
        Some(Action::Light(dx, dy)) => assert!(dx < 0.0 && dy == 0.0),
        other => panic!("{other:?}"),
    }
}

#[test]
fn shells_stay_between_one_and_the_layers_above_the_skin() {
    let mut state = ViewState::new(4, true, false);
    assert_eq!(state.shells, 3);
    assert!(matches!(state.apply(Action::MoreShells), Outcome::Refused(_)));
    for expected in [2, 1] {
        assert_eq!(state.apply(Action::FewerShells), Outcome::Redraw);
        assert_eq!(state.shells, expected);
    }
    assert!(matches!(state.apply(Action::FewerShells), Outcome::Refused(_)));
    assert_eq!(state.shells, 1);
    // A skin-only volume has no shells to add or remove.
    let mut bald = ViewState::new(1, false, false);
    assert_eq!(bald.shells, 0);
    assert!(matches!(bald.apply(Action::MoreShells), Outcome::Refused(_)));
}

#[test]
fn prt_is_refused_without_transfer() {
    let mut state = ViewState::new(8, false, false);
    assert!(matches!(state.apply(Action::Prt), Outcome::Refused(m) if m.contains("transfer")));
    assert!(!state.prt);
    let mut state = ViewState::new(8, true, false);
    assert_eq!(state.apply(Action::Prt), Outcome::Redraw);
    assert!(matches!(state.lighting().model, LightModel::Prt(_)));
    assert_eq!(state.apply(Action::Prt), Outcome::Unchanged);
    assert_eq!(state.apply(Action::KajiyaKay), Outcome::Redraw);
    assert!(matches!(state.lighting().model, LightModel::KajiyaKay(_)));
}

#[test]
fn settings_follow_the_toggles() {
    let mut state = ViewState::new(8, false, false);
    let s = state.settings();
    assert_eq!((s.shell_count, s.lod, s.fins), (Some(7), false, true));
    state.apply(Action::ToggleFins);
    state.apply(Action::ToggleLod);
    state.apply(Action::FewerShells);
    let s = state.settings();
    // With LOD the shell count is LOD's to choose, up to the user's count.
    assert_eq!(
        (s.shell_count, s.lod, s.fins, s.max_shells),
        (None, true, false, 6)
    );
    assert!(s.min_shells <= s.max_shells);
}

#[test]
fn reset_brings_the_camera_back_but_keeps_the_rest() {
    let mut state = ViewState::new(8, false, false);
    let start = state.clone();
    state.apply(Action::Orbit(30.0, -20.0));
    state.apply(Action::Zoom(3.0));
    state.apply(Action::ToggleFins);
    assert_ne!(state.orbit, start.orbit);
    assert_eq!(state.apply(Action::Reset), Outcome::Redraw);
    assert_eq!(state.orbit, start.orbit);
    assert!(!state.fins);
}

#[test]
fn drags_orbit_with_the_left_button_and_turn_the_light_with_the_right() {
    let mut drag = Drag::default();
    assert_eq!(drag.moved(10.0, 10.0), None);
    drag.button(MouseButton::Left, ElementState::Pressed);
    assert_eq!(drag.moved(13.0, 8.0), Some(Action::Orbit(3.0, -2.0)));
    drag.button(MouseButton::Left, ElementState::Released);
    assert_eq!(drag.moved(14.0, 8.0), None);
    drag.button(MouseButton::Right, ElementState::Pressed);
    assert_eq!(drag.moved(14.0, 9.0), Some(Action::Light(0.0, 1.0)));
}

#[test]
fn planes_are_refused_without_slices_and_trace_the_fur_when_on() {
    let mut state = ViewState::new(8, false, false);
    assert!(matches!(state.apply(Action::TogglePlanes), Outcome::Refused(m) if m.contains("--planes")));
    assert_eq!(state.settings().shell_method, ShellMethod::Instanced);
    let mut state = ViewState::new(8, false, true);
    assert_eq!(state.apply(Action::ToggleMarched), Outcome::Redraw);
    assert_eq!(state.apply(Action::TogglePlanes), Outcome::Redraw);
    assert_eq!(state.settings().shell_method, ShellMethod::VirtualPlanes);
    assert_eq!(state.apply(Action::TogglePlanes), Outcome::Redraw);
    assert_eq!(state.settings().shell_method, ShellMethod::Marched);
}
