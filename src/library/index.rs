//! `LIB/index.html`: the library to browse in any web browser. Static, one file, its links
//! relative (the folder can be moved or served as it is), nothing fetched from elsewhere.

use std::fmt::Write;
use std::path::Path;

use super::{Fitted, GALLERY, ROWS};
use crate::error::Result;
use crate::litsphere::Outline;

/// Writes `dir/index.html` for the materials in `dir/NAME/`.
pub fn write(dir: &Path, fitted: &[Fitted]) -> Result<()> {
    let mut html = String::new();
    html.push_str(HEAD);
    let _ = writeln!(html, "<h1>MatCap library: {} materials</h1>", fitted.len());
    let _ = writeln!(
        html,
        "<p>Each picture beside its material on the bunny, under its key light and under the key light turned {}° to the other side. All at once: <a href=\"{GALLERY}\">{GALLERY}</a>.</p>",
        super::gallery::TURN_DEG
    );
    for f in fitted {
        entry(&mut html, f);
    }
    html.push_str("</body>\n</html>\n");
    crate::commit::write_atomic(&dir.join(super::INDEX), html.as_bytes())
}

const HEAD: &str = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>MatCap library</title>\n<style>\nbody { font-family: sans-serif; background: #181818; color: #ddd; margin: 2em; }\na { color: #8cf; }\nsection { margin: 1.5em 0; }\nimg { display: block; image-rendering: auto; }\ntable { border-collapse: collapse; }\ntd { padding: 0 1em 0 0; }\n</style>\n</head>\n<body>\n";

/// One material: its name, its gallery row, its files, its fit error, light and notes.
fn entry(html: &mut String, f: &Fitted) {
    let (name, href) = (escape(&f.name), encode(&f.name));
    let e = &f.errors;
    let _ = writeln!(html, "<section id=\"{href}\">\n<h2>{name}</h2>");
    let _ = writeln!(html, "<img src=\"{ROWS}/{href}.png\" alt=\"{name}: the picture and its material on the bunny under two lights\">");
    let _ = writeln!(
        html,
        "<p><a href=\"{href}/material.json\">material.json</a> · <a href=\"{href}/report.png\">report.png</a> · <a href=\"{href}/scene.gltf\">scene.gltf</a> · <a href=\"{href}/\">folder</a></p>"
    );
    let light = f.light;
    let how = match f.spread_deg {
        Some(s) => format!("estimated, sure to within {s:.0}°"),
        None => "as given".into(),
    };
    let _ = writeln!(html, "<table>");
    let _ = writeln!(html, "<tr><td>picture</td><td>{}</td></tr>", escape(&f.picture.display().to_string()));
    let _ = writeln!(html, "<tr><td>fit error</td><td>RMS {:.5}, relative {:.4}, max {:.4} over {} samples</td></tr>", e.rms, e.rms_relative, e.max, f.samples);
    let _ = writeln!(html, "<tr><td>key light</td><td>({:.2}, {:.2}, {:.2}) {how}</td></tr>", light.x, light.y, light.z);
    let _ = writeln!(html, "<tr><td>outline</td><td>{}</td></tr>\n</table>", outline(f.outline));
    if !f.notes.is_empty() {
        let _ = writeln!(html, "<ul>");
        for note in &f.notes {
            let _ = writeln!(html, "<li>{}</li>", escape(note));
        }
        let _ = writeln!(html, "</ul>");
    }
    let _ = writeln!(html, "</section>");
}

fn outline(o: Outline) -> &'static str {
    match o {
        Outline::Alpha => "from the picture's alpha",
        Outline::Background => "from its background",
        Outline::Inscribed => "a MatCap: the disk inscribed in the square",
        Outline::Edges => "from the arc its edges show",
        Outline::Faint => "from a faint arc: check it",
        Outline::Given => "given by hand",
    }
}

/// `text` safe in HTML text and attribute values.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// A folder or file name as one relative URL path segment: every byte but the unreserved
/// ones percent-encoded (a name may hold spaces, `#`, `?` or `%`).
pub fn encode(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for b in name.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
            out.push(b as char);
        } else {
            let _ = write!(out, "%{b:02X}");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_escaped_in_text_and_encoded_in_links() {
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
        assert_eq!(encode("my matcap #2"), "my%20matcap%20%232");
        assert_eq!(encode("é"), "%C3%A9");
    }
}
