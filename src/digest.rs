//! Content digests: the lower-case hex SHA-256 every output uses to name bytes (the process file,
//! the masks, the manifest).

use sha2::{Digest, Sha256};

/// Lower-case hex SHA-256 of `bytes`.
///
/// ```
/// assert_eq!(
///     tactfab::digest::sha256_hex(b"abc"),
///     "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
/// );
/// ```
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}
