//! The viewer's UI driven headless, frame by frame, through egui with scripted input (the
//! same `Studio::handle_input` → `Studio::ui` → `Studio::after` order as the window): keyboard
//! shortcuts wherever egui's focus is, a side panel of stable width, status and timing in
//! sight at 1280×800, labels that never wrap inside a word, a status that tells the state.
#![cfg(feature = "viewer")]

use brdfpaint::gl::HeadlessContext;
use brdfpaint::render::Renderer;
use brdfpaint::viewer::{Mode, Start, Studio, PANEL_WIDTH};
use egui::{Event, Key, Modifiers, PointerButton, Pos2, Rect};

/// A file dropped on the window, as the window's integration hands it to egui.
#[derive(Debug)]
struct Dropped(std::path::PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &std::path::Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

struct Harness {
    ctx: egui::Context,
    studio: Studio,
    renderer: Renderer,
    _gl: HeadlessContext,
    last: Option<egui::FullOutput>,
}

impl Harness {
    fn new(mode: Mode) -> Harness {
        let gl = HeadlessContext::new().unwrap();
        let mut renderer = Renderer::new(gl.gl()).unwrap();
        let start = Start {
            model: ("sphere".into(), brdfpaint::scene::builtin_model("sphere").unwrap()),
            material: None,
            scene: None,
            watch: None,
            paint_model: "sphere".into(),
            size: 96,
            mode,
            render_scale: Some(1.0),
            uv: Default::default(),
        };
        let studio = Studio::new(&mut renderer, start).unwrap();
        let mut h = Harness { ctx: egui::Context::default(), studio, renderer, _gl: gl, last: None };
        // egui sizes panels over its first frames.
        for _ in 0..4 {
            h.frame(vec![]);
        }
        h
    }

    /// One frame at 1280×800 (one point per pixel) with these input events.
    fn frame(&mut self, events: Vec<Event>) {
        self.frame_with_drops(events, Vec::new());
    }

    /// One frame with these input events and these files dropped on the window.
    fn frame_with_drops(&mut self, events: Vec<Event>, dropped: Vec<std::path::PathBuf>) {
        let mut raw = egui::RawInput {
            screen_rect: Some(Rect::from_min_size(Pos2::ZERO, egui::vec2(1280.0, 800.0))),
            events,
            dropped_files: dropped.into_iter().map(|p| std::sync::Arc::new(Dropped(p)) as egui::DroppedFileHandle).collect(),
            ..Default::default()
        };
        // The window's order: background work, shortcuts, the UI, the refit.
        self.studio.tick(&mut self.renderer);
        self.studio.handle_input(&self.ctx, &mut raw);
        let (studio, renderer) = (&mut self.studio, &mut self.renderer);
        let out = self.ctx.run_ui(raw, |ui| studio.ui(renderer, ui));
        self.studio.after(&mut self.renderer);
        // The window reports its frame times here; any will do.
        self.studio.frame_done(20.0, 10.0, 25.0);
        self.last = Some(out);
    }

    fn key(&mut self, key: Key, modifiers: Modifiers) {
        let e = |pressed| Event::Key { key, physical_key: None, pressed, repeat: false, modifiers };
        self.frame(vec![e(true)]);
        self.frame(vec![e(false)]);
    }

    fn click(&mut self, p: Pos2) {
        let button = |pressed| Event::PointerButton { pos: p, button: PointerButton::Primary, pressed, modifiers: Modifiers::NONE };
        self.frame(vec![Event::PointerMoved(p)]);
        self.frame(vec![button(true)]);
        self.frame(vec![button(false)]);
    }

    /// A drag from `a` to `b` with the primary button.
    fn drag(&mut self, a: Pos2, b: Pos2) {
        let button = |p, pressed| Event::PointerButton { pos: p, button: PointerButton::Primary, pressed, modifiers: Modifiers::NONE };
        self.frame(vec![Event::PointerMoved(a)]);
        self.frame(vec![button(a, true)]);
        for k in 1..=8 {
            self.frame(vec![Event::PointerMoved(a + (b - a) * (k as f32 / 8.0))]);
        }
        self.frame(vec![button(b, false)]);
        self.frame(vec![]);
    }

    /// Every text drawn in the last frame: its string, its rectangle, and its rows' texts.
    fn texts(&self) -> Vec<(String, Rect, Vec<String>)> {
        fn walk(shape: &egui::epaint::Shape, clip: Rect, out: &mut Vec<(String, Rect, Vec<String>)>) {
            match shape {
                egui::epaint::Shape::Text(t) => {
                    // A row that ends a paragraph ("\n") is not a wrap: marked by a trailing '\n'.
                    let rows = t
                        .galley
                        .rows
                        .iter()
                        .map(|r| {
                            let mut s: String = r.row.glyphs.iter().map(|g| g.chr).collect();
                            if r.ends_with_newline {
                                s.push('\n');
                            }
                            s
                        })
                        .collect();
                    let rect = Rect::from_min_size(t.pos, t.galley.size()).intersect(clip);
                    out.push((t.galley.text().to_string(), rect, rows));
                    let _ = t;
                }
                egui::epaint::Shape::Vec(v) => v.iter().for_each(|s| walk(s, clip, out)),
                _ => {}
            }
        }
        let mut out = Vec::new();
        for c in &self.last.as_ref().unwrap().shapes {
            walk(&c.shape, c.clip_rect, &mut out);
        }
        out
    }

    /// The centre of the (first) text that is exactly `label`.
    fn find(&self, label: &str) -> Pos2 {
        let texts = self.texts();
        let hit = texts.iter().find(|t| t.0 == label).unwrap_or_else(|| panic!("no text '{label}' drawn"));
        hit.1.center()
    }

    /// The centre of the first text `label` drawn below the text `above` (a row's label).
    fn find_after(&self, label: &str, above: &str) -> Pos2 {
        let y = self.find(above).y - 2.0;
        let texts = self.texts();
        let hit = texts.iter().find(|t| t.0 == label && t.1.center().y >= y);
        hit.unwrap_or_else(|| panic!("no text '{label}' drawn below '{above}'")).1.center()
    }

    /// Puts egui's keyboard focus on a widget that is not a text field, the way a user's
    /// Shift+Tab does (egui's own focus navigation; the viewer leaves Shift+Tab to egui).
    fn focus_a_button(&mut self) {
        self.key(Key::Tab, Modifiers::SHIFT);
        let focused = self.ctx.memory(|m| m.focused());
        assert!(focused.is_some(), "Shift+Tab put egui's focus on a widget");
        assert!(!self.ctx.text_edit_focused(), "the focused widget is not a text field");
    }

    /// The middle of the canvas (paint mode: the square left of the 3D view).
    fn canvas_centre(&self) -> Pos2 {
        let view = self.studio.layout.view_rect.expect("a 3D view");
        let side = view.x as f32 - 4.0 - PANEL_WIDTH;
        Pos2::new(PANEL_WIDTH + side / 2.0, side / 2.0)
    }
}

#[test]
fn tab_switches_modes_both_ways_and_ctrl_z_undoes_with_egui_focus_on_a_button() {
    let mut h = Harness::new(Mode::View);
    // The user clicks the Paint button: the mode switches, by the mouse.
    let paint = h.find("Paint");
    h.click(paint);
    assert_eq!(h.studio.mode, Mode::Paint);
    // With egui's focus ring on a widget (before: Tab moved the ring instead of switching
    // back, and the focused widget swallowed Ctrl+Z), Tab switches both ways.
    h.focus_a_button();
    h.key(Key::Tab, Modifiers::NONE);
    assert_eq!(h.studio.mode, Mode::View, "the first Tab");
    h.focus_a_button();
    h.key(Key::Tab, Modifiers::NONE);
    assert_eq!(h.studio.mode, Mode::Paint, "the second Tab switches back");

    // A stroke on the canvas, then Ctrl+Z with the focus on a button: the painting is the
    // one before the stroke again, exactly; Ctrl+Shift+Z brings the stroke back.
    let before = h.studio.session().views[0].canvas.painting().clone();
    let c = h.canvas_centre();
    h.drag(c, c + egui::vec2(40.0, 20.0));
    let after = h.studio.session().views[0].canvas.painting().clone();
    let changed = (0..before.alpha.len()).filter(|&k| before.pixels[k] != after.pixels[k]).count();
    assert!(changed > 100, "the stroke painted {changed} pixels");
    h.focus_a_button();
    h.key(Key::Z, Modifiers::COMMAND);
    assert!(h.studio.session().views[0].canvas.painting() == &before, "Ctrl+Z undid the stroke");
    h.focus_a_button();
    h.key(Key::Z, Modifiers::COMMAND | Modifiers::SHIFT);
    assert!(h.studio.session().views[0].canvas.painting() == &after, "Ctrl+Shift+Z redid it");
    // B, E, F and the brackets work with the focus on a button too: E then a stroke erases.
    h.focus_a_button();
    h.key(Key::E, Modifiers::NONE);
    h.key(Key::CloseBracket, Modifiers::NONE);
    h.drag(c, c + egui::vec2(1.0, 0.0));
    let erased = h.studio.session().views[0].canvas.painting();
    let unpainted = erased.alpha.iter().filter(|&&a| a == 0.0).count();
    let before_unpainted = after.alpha.iter().filter(|&&a| a == 0.0).count();
    // The default 16 px brush grown by 1.25 is 20 px; of hardness 0.7 it erases completely
    // within 0.7 x 20 = 14 px: about pi 14^2 = 616 pixels (the 16 px brush: 394).
    assert!(unpainted > before_unpainted + 500, "E and ] made an eraser of radius 20: {} more unpainted", unpainted - before_unpainted);
}

#[test]
fn the_panel_keeps_its_width_when_timings_appear_and_status_and_timing_are_in_sight() {
    let mut h = Harness::new(Mode::Paint);
    let width0 = h.studio.layout.panel_rect.unwrap().width;
    let view0 = h.studio.layout.view_rect.unwrap();
    assert!(h.studio.timings().count == 0);
    let c = h.canvas_centre();
    h.drag(c, c + egui::vec2(30.0, 30.0));
    assert!(h.studio.timings().count > 0, "the stroke was timed");
    h.frame(vec![]);
    let width1 = h.studio.layout.panel_rect.unwrap().width;
    // Before: 300 px, then about 331 once the timing text was there.
    assert_eq!((width0, width1), (PANEL_WIDTH as i32, PANEL_WIDTH as i32));
    assert_eq!(h.studio.layout.view_rect.unwrap(), view0, "the canvas and 3D view did not move");

    // The stroke -> frame summary and the status line are drawn inside the window, in the
    // panel (they used to be below its fold at 1280x800).
    let texts = h.texts();
    let visible = |prefix: &str| {
        let t = texts.iter().find(|t| t.0.starts_with(prefix)).unwrap_or_else(|| panic!("no '{prefix}…' drawn"));
        assert!(t.1.height() > 5.0 && t.1.max.y <= 800.0 && t.1.max.x <= PANEL_WIDTH, "'{}' at {:?}", t.0, t.1);
    };
    visible("stroke -> frame ");
    visible("painting view 'front-left'");
}

#[test]
fn no_label_wraps_inside_a_word() {
    for mode in [Mode::View, Mode::Paint] {
        let mut h = Harness::new(mode);
        let c = h.canvas_centre();
        if mode == Mode::Paint {
            h.drag(c, c + egui::vec2(20.0, 0.0));
        }
        let mut checked = 0;
        for (text, _, rows) in h.texts() {
            for pair in rows.windows(2) {
                let (a, b) = (pair[0].chars().last(), pair[1].chars().next());
                if let (Some(a), Some(b)) = (a, b) {
                    assert!(!(a.is_alphanumeric() && b.is_alphanumeric()), "{mode:?}: '{text}' wraps inside a word: {rows:?}");
                }
                checked += 1;
            }
        }
        assert!(checked > 3, "{mode:?}: {checked} wrapped rows checked");
    }
}

/// Texts of the last frame that start in the side panel but run past its right edge (where
/// they are clipped: a hint wrapped out of sight, a box wider than the panel).
fn panel_overflow(h: &Harness) -> Vec<String> {
    fn walk(shape: &egui::epaint::Shape, out: &mut Vec<String>) {
        match shape {
            egui::epaint::Shape::Text(t) => {
                let r = Rect::from_min_size(t.pos, t.galley.size());
                if r.min.x < PANEL_WIDTH && r.max.x > PANEL_WIDTH - 4.0 {
                    out.push(format!("'{}' to x = {:.0}", t.galley.text(), r.max.x));
                }
            }
            egui::epaint::Shape::Vec(v) => v.iter().for_each(|s| walk(s, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for c in &h.last.as_ref().unwrap().shapes {
        walk(&c.shape, &mut out);
    }
    out
}

#[test]
fn a_long_material_name_keeps_the_panel_inside_its_edge() {
    let dir = tempfile::tempdir().unwrap();
    let long = dir.path().join("red-plastic-painted-by-hand-with-brush-strokes-v3-final");
    std::fs::create_dir(&long).unwrap();
    for f in std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/material-v1")).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(&f, long.join(f.file_name().unwrap())).unwrap();
    }
    let mut h = Harness::new(Mode::View);
    assert!(panel_overflow(&h).is_empty(), "before: {:?}", panel_overflow(&h));
    h.frame_with_drops(vec![], vec![long]);
    for _ in 0..3 {
        h.frame(vec![]);
    }
    let drawn: Vec<String> = h.texts().into_iter().map(|t| t.0).collect();
    assert!(drawn.iter().any(|t| t.contains("brush-strokes")), "the material is open: {drawn:?}");
    // Measured before the combo boxes truncated their text: the material box ran to
    // x = 318 and the hint below it wrapped at 318, clipped at the panel's edge.
    assert!(panel_overflow(&h).is_empty(), "{:?}", panel_overflow(&h));
}

#[test]
fn the_status_tells_the_current_state() {
    let mut h = Harness::new(Mode::Paint);
    assert!(h.studio.status().contains("example painting fitted"), "{}", h.studio.status());
    // Clearing the canvas: the example's note is gone and the state says nothing is painted.
    // Fold the sections above the paint tools, so the Clear button is in the panel's view.
    for header in ["Model and material", "Camera and light", "Fit"] {
        let p = h.find(header);
        h.click(p);
    }
    // Folding is animated (egui steps 1/60 s a frame here).
    for _ in 0..30 {
        h.frame(vec![]);
    }
    let clear = h.find("Clear");
    h.click(clear);
    let s = h.studio.status();
    assert!(!s.contains("example painting") && s.contains("nothing painted"), "{s}");
    // Loading another material: the status names it.
    let dir = tempfile::tempdir().unwrap();
    let saved = dir.path().join("other");
    let mut h = Harness::new(Mode::View);
    h.studio.current_material().unwrap().save(&saved).unwrap();
    h.studio.open_file(&mut h.renderer, &saved).unwrap();
    h.frame(vec![]);
    let s = h.studio.status();
    assert!(!s.contains("example painting") && s.contains("material other") && s.contains("opened material"), "{s}");
}

/// Frames until `done` holds (background renders and prepares land between them), at most
/// 60 s.
fn frames_until(h: &mut Harness, what: &str, done: impl Fn(&Studio) -> bool) {
    let start = std::time::Instant::now();
    while !done(&h.studio) {
        assert!(start.elapsed().as_secs() < 60, "waited a minute for {what}: {}", h.studio.status());
        std::thread::sleep(std::time::Duration::from_millis(20));
        h.frame(vec![]);
    }
}

#[test]
fn a_dropped_matcap_is_a_lit_sphere_with_the_estimated_light_whose_sun_drags_the_fit() {
    use brdfpaint::litsphere::{estimate_light, Picture, MAX_SIDE};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/matcaps/blender_cc0/exr/clay_studio.exr");
    let mut h = Harness::new(Mode::View);
    let example = h.studio.current_material().unwrap().clone();
    // Square, like the standard views, but its disk is not where their sphere is: no question.
    h.frame_with_drops(vec![], vec![path.clone()]);
    assert!(h.studio.error().is_none(), "{:?}", h.studio.error());
    let picture = Picture::read(&path, MAX_SIDE).unwrap();
    let estimated = estimate_light(&picture.painting, &picture.disk).unwrap();
    let sphere = h.studio.lit_sphere().expect("a lit-sphere session");
    assert_eq!(sphere.light(), estimated.direction);
    assert_eq!(sphere.picture.disk, picture.disk);
    assert_eq!(h.studio.mode, Mode::Paint);
    assert_eq!(h.studio.session().views.len(), 1);
    assert!(h.studio.status().contains("light estimated at"), "{}", h.studio.status());
    // The panel says where the light is and how sure the estimate is.
    let e = estimated.direction;
    let shown = format!("light ({:.2}, {:.2}, {:.2})", e.x, e.y, e.z);
    assert!(h.texts().iter().any(|t| t.0 == shown), "no '{shown}' in the panel");
    assert!(h.texts().iter().any(|t| t.0.contains(&format!("sure to within {:.0}°", estimated.spread_deg))));
    for (text, _, rows) in h.texts() {
        for pair in rows.windows(2) {
            let (a, b) = (pair[0].chars().last(), pair[1].chars().next());
            assert!(!(a.is_some_and(char::is_alphanumeric) && b.is_some_and(char::is_alphanumeric)), "'{text}' wraps inside a word: {rows:?}");
        }
    }
    frames_until(&mut h, "the lit sphere's fit", |s| !s.preparing() && s.current_material().is_some_and(|m| *m != example));
    let fitted = h.studio.current_material().unwrap().clone();

    // The sun sits over the sphere where the light is; dragging it to the upper right moves
    // the light there and the fit follows, while the picture stays as it was.
    let view = h.studio.layout.view_rect.unwrap();
    let side = view.x as f32 - 4.0 - PANEL_WIDTH;
    let scale = side / picture.painting.width as f32;
    let d = picture.disk;
    let centre = Pos2::new(PANEL_WIDTH + d.cx as f32 * scale, d.cy as f32 * scale);
    let radius = d.r as f32 * scale;
    let sun = centre + egui::vec2(e.x as f32, -e.y as f32) * radius;
    let target = glam::DVec3::new(0.6, 0.5, (1.0f64 - 0.36 - 0.25).sqrt());
    let to = centre + egui::vec2(0.6, -0.5) * radius;
    let painting = h.studio.session().views[0].canvas.painting().clone();
    h.drag(sun, to);
    let asked = h.studio.lit_sphere().unwrap().light();
    assert!(asked.angle_between(target).to_degrees() < 0.5, "the light followed the sun: {asked} vs {target}");
    assert!(h.studio.session().views[0].canvas.painting() == &painting, "dragging the sun does not paint");
    // The 3D view is lit from there too, in its camera's frame.
    let towards = h.studio.stage.orbit.world_from_camera().transform_vector3(asked.as_vec3());
    assert!((h.studio.stage.light.direction() - towards).length() < 1e-4);
    frames_until(&mut h, "the refit under the dragged light", |s| {
        !s.preparing() && s.lit_sphere().is_some_and(|l| l.applied_light() == asked)
    });
    let refitted = h.studio.current_material().unwrap();
    assert!(*refitted != fitted, "the fit moved with the light");
}

/// The disk a lit sphere was read with is drawn over it: dragging its outline inwards reads
/// the picture again with the smaller disk (as `fit --disk` would), and dragging its centre
/// cross moves it; the status gives the disk in the file's pixels.
#[test]
fn the_disk_of_a_lit_sphere_drags_to_a_new_radius_and_centre() {
    use brdfpaint::litsphere::{Picture, MAX_SIDE};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/matcaps/blender_cc0/exr/clay_studio.exr");
    let mut h = Harness::new(Mode::View);
    h.frame_with_drops(vec![], vec![path.clone()]);
    let picture = Picture::read(&path, MAX_SIDE).unwrap();
    let view = h.studio.layout.view_rect.unwrap();
    let scale = (view.x as f32 - 4.0 - PANEL_WIDTH) / picture.painting.width as f32;
    let d = picture.disk;
    let centre = Pos2::new(PANEL_WIDTH + d.cx as f32 * scale, d.cy as f32 * scale);
    let radius = d.r as f32 * scale;
    // Grab the outline on the side away from the sun.
    let e = h.studio.lit_sphere().unwrap().light();
    let away = -egui::vec2(e.x as f32, -e.y as f32).normalized();
    let away = if away.is_finite() { away } else { egui::vec2(1.0, 0.0) };
    h.drag(centre + away * radius, centre + away * (radius - 30.0));
    h.frame(vec![]);
    let smaller = h.studio.lit_sphere().expect("still a lit sphere").picture.disk;
    let want = d.r - 30.0 / scale as f64;
    assert!((smaller.r - want).abs() < 1.5, "radius {} after the drag, {want} asked", smaller.r);
    assert!((smaller.cx - d.cx).abs() < 0.01 && (smaller.cy - d.cy).abs() < 0.01, "the centre stays: {smaller:?}");
    assert!(h.studio.status().contains("disk at (") && h.studio.status().contains("as dragged"), "{}", h.studio.status());
    eprintln!("light {e}; disk {d:?} -> {smaller:?}");
    // The centre cross moves it (the sun is elsewhere unless the light is at the viewer).
    if e.truncate().length() * radius as f64 > 20.0 {
        h.drag(centre, centre + egui::vec2(-10.0, 6.0));
        h.frame(vec![]);
        let moved = h.studio.lit_sphere().unwrap().picture.disk;
        assert!((moved.cx - (d.cx - 10.0 / scale as f64)).abs() < 1.0 && (moved.cy - (d.cy + 6.0 / scale as f64)).abs() < 1.0, "{moved:?}");
        assert!((moved.r - smaller.r).abs() < 0.01, "{moved:?}");
        eprintln!("moved to {moved:?}");
    }
}

#[test]
fn a_dropped_painting_of_the_sphere_view_asks_whether_it_is_a_lit_sphere() {
    let mut h = Harness::new(Mode::Paint);
    // The active view's own reference, transparent around the object: a painting of that
    // view, and a picture of a sphere too.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sphere-view.png");
    let reference = h.studio.session().views[0].reference_painting();
    std::fs::write(&path, reference.encode_png16().unwrap()).unwrap();
    h.frame_with_drops(vec![], vec![path.clone()]);
    h.frame(vec![]);
    assert!(h.studio.lit_sphere().is_none(), "not taken as a lit sphere without asking");
    let answer = h.find("Painting of view 'front-left'");
    h.click(answer);
    assert!(h.studio.lit_sphere().is_none());
    assert!(h.studio.status().contains("sphere-view.png"), "{}", h.studio.status());
    assert!(h.studio.error().is_none(), "{:?}", h.studio.error());
}

/// The middle of the 3D view.
fn view_centre(h: &Harness) -> Pos2 {
    let v = h.studio.layout.view_rect.expect("a 3D view");
    Pos2::new(v.x as f32 + v.width as f32 / 2.0, v.y as f32 + v.height as f32 / 2.0)
}

#[test]
fn an_environment_chosen_in_the_panel_turns_by_the_alt_dragged_angle_and_a_plain_drag_orbits() {
    let mut h = Harness::new(Mode::View);
    assert_eq!(h.studio.environment().name(), "none");
    let menu = h.find_after("none", "environment");
    h.click(menu);
    h.frame(vec![]);
    let city = h.find("city");
    h.click(city);
    assert_eq!(h.studio.environment().name(), "city", "{}", h.studio.status());
    assert!(h.studio.error().is_none(), "{:?}", h.studio.error());
    assert!(h.studio.status().contains("environment city"), "{}", h.studio.status());

    let c = view_centre(&h);
    let yaw = h.studio.stage.orbit.yaw;
    h.frame(vec![Event::ModifiersChanged(Modifiers::ALT)]);
    h.drag(c, c + egui::vec2(100.0, 0.0));
    h.frame(vec![Event::ModifiersChanged(Modifiers::NONE)]);
    // 0.5° per point dragged; egui's drag starts a few points in, so allow one step of the drag.
    let turned = h.studio.environment().rotate_deg;
    assert!((turned - 50.0).abs() <= 6.25 + 1e-3, "Alt-drag by 100 points turned the environment {turned}°");
    assert_eq!(h.studio.stage.orbit.yaw, yaw, "Alt-drag does not orbit the camera");
    // Back the other way: the same angle the other way.
    h.frame(vec![Event::ModifiersChanged(Modifiers::ALT)]);
    h.drag(c, c - egui::vec2(100.0, 0.0));
    h.frame(vec![Event::ModifiersChanged(Modifiers::NONE)]);
    assert!(h.studio.environment().rotate_deg.abs() <= 1e-3, "{}", h.studio.environment().rotate_deg);

    h.drag(c, c + egui::vec2(100.0, 0.0));
    assert!(h.studio.environment().rotate_deg.abs() <= 1e-3, "a plain drag leaves the environment");
    assert_ne!(h.studio.stage.orbit.yaw, yaw, "a plain drag orbits");
    // A still frame with the full count of directions follows the moving ones.
    assert!(!h.studio.busy() || h.studio.environment().samples_now() == h.studio.environment().samples);
}

#[test]
fn a_dropped_bad_hdr_keeps_the_environment_and_says_why_in_one_line() {
    let mut h = Harness::new(Mode::View);
    let menu = h.find_after("none", "environment");
    h.click(menu);
    h.frame(vec![]);
    let sunset = h.find("sunset");
    h.click(sunset);
    assert_eq!(h.studio.environment().name(), "sunset");
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken.hdr");
    std::fs::write(&bad, b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n\x02\x02").unwrap();
    h.frame_with_drops(vec![], vec![bad.clone()]);
    h.frame(vec![]);
    assert_eq!(h.studio.environment().name(), "sunset", "the previous environment stays");
    let e = h.studio.error().expect("an error line").to_string();
    assert!(!e.contains('\n') && e.contains("broken.hdr"), "one line naming the file: {e}");
    // A good one dropped after it is taken, and clears the error.
    let good = dir.path().join("grey.hdr");
    let img = image::Rgb32FImage::from_pixel(16, 8, image::Rgb([0.5, 0.5, 0.5]));
    img.save(&good).unwrap();
    h.frame_with_drops(vec![], vec![good.clone()]);
    assert_eq!(h.studio.environment().name(), good.display().to_string());
    assert!(h.studio.error().is_none(), "{:?}", h.studio.error());
}

#[test]
fn page_down_and_the_arrows_step_through_an_opened_library() {
    let mut h = Harness::new(Mode::View);
    let live = h.studio.current_material().cloned().expect("the example painting's fit");
    let materials = ["clay", "jade", "toon"].iter().map(|n| (n.to_string(), live.clone())).collect();
    h.studio.open_library("lib", materials);
    h.frame(vec![]);
    assert_eq!(h.studio.material_name(), "clay");
    let mut seen = Vec::new();
    for key in [Key::PageDown, Key::PageDown, Key::ArrowRight, Key::ArrowLeft, Key::PageUp] {
        h.key(key, Modifiers::NONE);
        seen.push(h.studio.material_name().to_string());
    }
    // Around the list both ways; the live painting's material is not a stop.
    assert_eq!(seen, ["jade", "toon", "clay", "toon", "jade"]);
}
