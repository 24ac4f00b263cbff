//! Keyboard shortcuts that work wherever egui's focus is.
//!
//! egui moves its keyboard focus with Tab (and the arrow keys) before any widget runs, and a
//! focused button takes the keys after that: with its focus ring on a button, Tab would move
//! the ring instead of switching modes, and Ctrl+Z would do nothing. So the shortcuts are
//! taken out of the frame's input before egui sees it, unless a text field is being edited
//! (where the keys are the text's).

use egui::{Event, Key, Modifiers};

use super::tools::Tool;

/// What a shortcut asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shortcut {
    /// Tab: view ↔ paint.
    ToggleMode,
    /// Ctrl+Z.
    Undo,
    /// Ctrl+Shift+Z or Ctrl+Y.
    Redo,
    /// B, E, F.
    Tool(Tool),
    /// `[`.
    Smaller,
    /// `]`.
    Larger,
    /// Page Down or →: the next material of the list (a library's).
    NextMaterial,
    /// Page Up or ←.
    PreviousMaterial,
}

/// The shortcut a key press is, if any.
fn shortcut(key: Key, m: Modifiers, repeat: bool) -> Option<Shortcut> {
    let plain = !(m.ctrl || m.command || m.alt || m.mac_cmd);
    match key {
        // A held Tab would flicker between the modes.
        Key::Tab if plain && !m.shift && !repeat => Some(Shortcut::ToggleMode),
        Key::Z if m.command && !m.alt && !m.shift => Some(Shortcut::Undo),
        Key::Z if m.command && !m.alt && m.shift => Some(Shortcut::Redo),
        Key::Y if m.command && !m.alt && !m.shift => Some(Shortcut::Redo),
        Key::B if plain && !repeat => Some(Shortcut::Tool(Tool::Brush)),
        Key::E if plain && !repeat => Some(Shortcut::Tool(Tool::Eraser)),
        Key::F if plain && !repeat => Some(Shortcut::Tool(Tool::Fill)),
        Key::OpenBracket if plain => Some(Shortcut::Smaller),
        Key::CloseBracket if plain => Some(Shortcut::Larger),
        Key::PageDown | Key::ArrowRight if plain && !m.shift => Some(Shortcut::NextMaterial),
        Key::PageUp | Key::ArrowLeft if plain && !m.shift => Some(Shortcut::PreviousMaterial),
        _ => None,
    }
}

/// Takes the shortcuts out of a frame's input events, in order. With `text_editing` (a text
/// field has the focus) nothing is taken. Their key releases go too, so no widget sees half
/// a key.
pub fn take_shortcuts(events: &mut Vec<Event>, text_editing: bool) -> Vec<Shortcut> {
    if text_editing {
        return Vec::new();
    }
    let mut taken = Vec::new();
    events.retain(|e| {
        let Event::Key { key, pressed, repeat, modifiers, .. } = e else { return true };
        // A release is a shortcut's when its press would be (repeat flags aside).
        match (shortcut(*key, *modifiers, false), *pressed) {
            (Some(_), false) => false,
            (Some(_), true) => {
                if let Some(s) = shortcut(*key, *modifiers, *repeat) {
                    taken.push(s);
                }
                false
            }
            (None, _) => true,
        }
    });
    taken
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(key: Key, modifiers: Modifiers, pressed: bool) -> Event {
        Event::Key { key, physical_key: None, pressed, repeat: false, modifiers }
    }

    #[test]
    fn shortcuts_are_taken_out_and_other_keys_stay() {
        let mut events = vec![
            key(Key::Tab, Modifiers::NONE, true),
            key(Key::Tab, Modifiers::NONE, false),
            key(Key::Z, Modifiers::COMMAND, true),
            key(Key::Z, Modifiers::COMMAND | Modifiers::SHIFT, true),
            key(Key::A, Modifiers::NONE, true),
            Event::Text("b".into()),
            key(Key::B, Modifiers::NONE, true),
            key(Key::OpenBracket, Modifiers::NONE, true),
            key(Key::Tab, Modifiers::SHIFT, true),
        ];
        let taken = take_shortcuts(&mut events, false);
        assert_eq!(
            taken,
            [Shortcut::ToggleMode, Shortcut::Undo, Shortcut::Redo, Shortcut::Tool(Tool::Brush), Shortcut::Smaller]
        );
        // A and the text stay; so does Shift+Tab (egui's "focus back").
        assert_eq!(events.len(), 3, "{events:?}");
        assert!(matches!(events[0], Event::Key { key: Key::A, .. }));
        assert!(matches!(events[2], Event::Key { key: Key::Tab, .. }));
    }

    #[test]
    fn a_text_field_being_edited_keeps_every_key() {
        let mut events = vec![key(Key::B, Modifiers::NONE, true), key(Key::Z, Modifiers::COMMAND, true)];
        assert!(take_shortcuts(&mut events, true).is_empty());
        assert_eq!(events.len(), 2);
    }

    #[test]
    fn a_held_tab_switches_once_and_ctrl_b_is_not_the_brush() {
        let mut events = vec![
            Event::Key { key: Key::Tab, physical_key: None, pressed: true, repeat: true, modifiers: Modifiers::NONE },
            key(Key::B, Modifiers::CTRL, true),
        ];
        assert!(take_shortcuts(&mut events, false).is_empty());
        assert_eq!(events.len(), 1, "the repeat is swallowed, Ctrl+B stays: {events:?}");
    }
}
