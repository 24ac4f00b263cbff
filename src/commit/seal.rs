//! A seal on the tool's own bookkeeping files (ownership records, rename journals): an
//! HMAC-SHA256 under a key only this user's brdfpaint knows, so a record or journal planted
//! in a folder, or copied from another machine, is not taken for one the tool wrote.
//!
//! The key is 32 random bytes in `$XDG_CONFIG_HOME/brdfpaint/owner.key` (else
//! `~/.config/brdfpaint/owner.key`), made on first use, readable by the user only. Where there
//! is no such folder the seal falls back to a fixed key: it then still tells the tool's files
//! from accidents, not from someone who forges them on purpose.

use std::path::PathBuf;
use std::sync::OnceLock;

use sha2::{Digest, Sha256};

/// Bytes of a key and of a seal.
const LEN: usize = 32;
/// SHA-256's block (RFC 2104: the key is padded to it).
const BLOCK: usize = 64;

/// The key, read or made once per process.
fn key() -> &'static [u8; LEN] {
    static KEY: OnceLock<[u8; LEN]> = OnceLock::new();
    KEY.get_or_init(|| key_path().and_then(|p| load_or_make(&p)).unwrap_or(*b"brdfpaint: no owner key on disk."))
}

fn key_path() -> Option<PathBuf> {
    let var = |k: &str| std::env::var_os(k).filter(|v| !v.is_empty()).map(PathBuf::from);
    var("XDG_CONFIG_HOME")
        .or_else(|| var("HOME").map(|h| h.join(".config")))
        .map(|d| d.join("brdfpaint").join("owner.key"))
}

/// The key at `path`, made there if missing (by one exclusive create, so two processes
/// starting together agree on the first one written).
fn load_or_make(path: &std::path::Path) -> Option<[u8; LEN]> {
    if let Some(key) = load(path) {
        return Some(key);
    }
    let fresh = random_key()?;
    std::fs::create_dir_all(path.parent()?).ok()?;
    let tmp = path.with_extension(format!("{}.tmp", std::process::id()));
    write_private(&tmp, &fresh).ok()?;
    // A hard link fails where the key exists: then the other process's key wins.
    let linked = std::fs::hard_link(&tmp, path);
    let _ = std::fs::remove_file(&tmp);
    match linked {
        Ok(()) => Some(fresh),
        Err(_) => load(path),
    }
}

fn load(path: &std::path::Path) -> Option<[u8; LEN]> {
    let bytes = crate::fsio::read_regular(path, LEN as u64).ok()?;
    bytes.try_into().ok()
}

fn write_private(path: &std::path::Path, key: &[u8; LEN]) -> std::io::Result<()> {
    use std::io::Write;
    let mut options = std::fs::OpenOptions::new();
    options.write(true).create_new(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.mode(0o600);
    }
    let mut f = options.open(path)?;
    f.write_all(key)?;
    f.sync_all()
}

fn random_key() -> Option<[u8; LEN]> {
    use std::io::Read;
    let mut key = [0u8; LEN];
    std::fs::File::open("/dev/urandom").ok()?.read_exact(&mut key).ok()?;
    Some(key)
}

/// The seal of `bytes`: HMAC-SHA256 (RFC 2104) under the user's key, in hex.
pub fn seal(bytes: &[u8]) -> String {
    hex(&hmac(key(), bytes))
}

/// `body` (lines, each ending in a newline) with a last line `seal HEX` that seals it.
pub fn close(body: &str) -> String {
    format!("{body}seal {}\n", seal(body.as_bytes()))
}

/// The body of a text made by [`close`], if its seal holds.
pub fn open(text: &str) -> Option<&str> {
    let lines = text.strip_suffix('\n')?;
    let start = lines.rfind('\n').map_or(0, |i| i + 1);
    let (body, last) = (&text[..start], &lines[start..]);
    verify(body.as_bytes(), last.strip_prefix("seal ")?).then_some(body)
}

/// Whether `seal` is the seal of `bytes`.
pub fn verify(bytes: &[u8], seal: &str) -> bool {
    let expected = self::seal(bytes);
    // Constant time: a forger learns nothing from how long a refusal takes.
    expected.len() == seal.len() && expected.bytes().zip(seal.bytes()).fold(0u8, |d, (a, b)| d | (a ^ b)) == 0
}

fn hmac(key: &[u8; LEN], message: &[u8]) -> [u8; LEN] {
    let mut pad = [0u8; BLOCK];
    pad[..LEN].copy_from_slice(key);
    let inner = Sha256::new().chain_update(pad.map(|b| b ^ 0x36)).chain_update(message).finalize();
    Sha256::new().chain_update(pad.map(|b| b ^ 0x5c)).chain_update(inner).finalize().into()
}

/// Lower-case hex of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hmac_matches_rfc_4231_case_2_shape() {
        // RFC 4231 test case 2 uses a 4-byte key ("Jefe"); padded with zeros to 32 bytes it is
        // the same HMAC, since the key is zero-padded to the block either way.
        let mut key = [0u8; LEN];
        key[..4].copy_from_slice(b"Jefe");
        let mac = hex(&hmac(&key, b"what do ya want for nothing?"));
        assert_eq!(mac, "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843");
    }

    #[test]
    fn a_seal_verifies_only_its_own_bytes() {
        let s = seal(b"material.json");
        assert!(verify(b"material.json", &s));
        assert!(!verify(b"material.jsoN", &s));
        assert!(!verify(b"material.json", &s[1..]));
        let text = close("a\tb\n");
        assert_eq!(open(&text), Some("a\tb\n"));
        assert_eq!(open(&close("")), Some(""));
        assert_eq!(open(&text.replace("a\t", "c\t")), None);
        assert_eq!(open("a\tb\n"), None);
    }
}
