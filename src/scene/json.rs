//! The JSON of a glTF file, read as exporters write it: an index or count written as a float
//! (`"mesh": 1.0`, which JSON allows and some tools emit) is read as the integer it is.

/// The JSON root and binary chunk of a .gltf or .glb file's bytes. Integral floats are
/// rewritten as integers ([`integral_floats_as_integers`]) only when the file does not parse
/// as it is; the error is then the first parse's.
pub(super) fn parse(bytes: &[u8]) -> Result<(gltf::json::Root, Option<Vec<u8>>), gltf::Error> {
    let (text, blob) = if bytes.starts_with(b"glTF") {
        let glb = gltf::binary::Glb::from_slice(bytes)?;
        (glb.json, glb.bin.map(|b| b.into_owned()))
    } else {
        (std::borrow::Cow::Borrowed(bytes), None)
    };
    match gltf::json::deserialize::from_slice(&text) {
        Ok(root) => Ok((root, blob)),
        Err(first) => match integral_floats_as_integers(&text) {
            Some(fixed) => gltf::json::deserialize::from_slice(&fixed).map(|root| (root, blob)).map_err(|_| first.into()),
            None => Err(first.into()),
        },
    }
}

/// `text` with every number of the form `-?digits.zeros` (no exponent) written as its
/// integer part, outside strings; `None` when there is none. Never longer than `text`.
pub(super) fn integral_floats_as_integers(text: &[u8]) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(text.len());
    let (mut i, mut changed, mut in_string) = (0, false, false);
    while i < text.len() {
        let c = text[i];
        if in_string {
            out.push(c);
            if c == b'\\' && i + 1 < text.len() {
                out.push(text[i + 1]);
                i += 1;
            } else if c == b'"' {
                in_string = false;
            }
            i += 1;
            continue;
        }
        if c == b'-' || c.is_ascii_digit() {
            let end = i + text[i..].iter().position(|b| !matches!(b, b'0'..=b'9' | b'.' | b'e' | b'E' | b'+' | b'-')).unwrap_or(text.len() - i);
            let token = &text[i..end];
            match integer_part(token) {
                Some(int) => {
                    out.extend_from_slice(int);
                    changed = true;
                }
                None => out.extend_from_slice(token),
            }
            i = end;
            continue;
        }
        in_string = c == b'"';
        out.push(c);
        i += 1;
    }
    changed.then_some(out)
}

/// The integer part of a number token written `-?digits.zeros`.
fn integer_part(token: &[u8]) -> Option<&[u8]> {
    let dot = token.iter().position(|&b| b == b'.')?;
    let (int, frac) = (&token[..dot], &token[dot + 1..]);
    let digits = int.strip_prefix(b"-").unwrap_or(int);
    let whole = !digits.is_empty() && digits.iter().all(u8::is_ascii_digit);
    (whole && !frac.is_empty() && frac.iter().all(|&b| b == b'0')).then_some(int)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integral_floats_become_integers_outside_strings_only() {
        let text = br#"{"mesh": 1.0, "count": -20.000, "yfov": 0.5, "e": 1.0e2, "name": "v1.0 \"2.0\"", "k": [3.0,4]}"#;
        let fixed = integral_floats_as_integers(text).unwrap();
        assert_eq!(
            std::str::from_utf8(&fixed).unwrap(),
            r#"{"mesh": 1, "count": -20, "yfov": 0.5, "e": 1.0e2, "name": "v1.0 \"2.0\"", "k": [3,4]}"#
        );
        assert_eq!(integral_floats_as_integers(br#"{"a": 1, "b": 0.25, "c": "1.0"}"#), None);
    }
}
