//! Reading the TOML configs of every subcommand (patch, sample, calibrate, md ...): one parser, whose
//! errors name the file, the key and its line. Every config type denies unknown keys
//! (`#[serde(deny_unknown_fields)]`); the toml crate points such an error at the key, except inside
//! internally tagged tables (a sample's `kind = ...`), where it points at the table header: there
//! the key's own line is found and added.

use std::path::Path;

use anyhow::{anyhow, Context, Result};
use serde::de::DeserializeOwned;

/// Parses `text` (from `origin`, for the message) as a `T`.
pub fn parse<T: DeserializeOwned>(text: &str, origin: &Path) -> Result<T> {
    toml::from_str(text).map_err(|e| {
        anyhow!("{}", with_key_position(text, &e.to_string()).trim_end())
            .context(format!("parsing {}", origin.display()))
    })
}

/// Reads and parses the config file `path`.
pub fn read<T: DeserializeOwned>(path: &Path) -> Result<T> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    parse(&text, path)
}

/// An error message about an unknown key, with the key's own line and column added when the
/// message does not already point at it (a message without an unknown key is returned as it is).
pub fn with_key_position(text: &str, message: &str) -> String {
    let Some(key) = unknown_key(message) else {
        return message.to_string();
    };
    // toml's message: "TOML parse error at line L, column C\n  |\nL | <source line>\n ...".
    let pointed_line = message
        .split_once("at line ")
        .and_then(|(_, rest)| rest.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|n| n.parse::<usize>().ok());
    let defines = |line: &str| {
        let l = line.trim_start();
        l.strip_prefix(key)
            .or_else(|| l.strip_prefix(&format!("\"{key}\"")))
            .is_some_and(|rest| rest.trim_start().starts_with('=') || rest.starts_with('.'))
    };
    let lines: Vec<&str> = text.lines().collect();
    if pointed_line.is_some_and(|n| n >= 1 && lines.get(n - 1).is_some_and(|l| defines(l))) {
        return message.to_string();
    }
    // The first definition of the key after the line the message points at (the table's header).
    let from = pointed_line.unwrap_or(1).saturating_sub(1);
    match (from..lines.len()).find(|&i| defines(lines[i])) {
        Some(i) => {
            let col = lines[i].len() - lines[i].trim_start().len() + 1;
            format!(
                "{}\n(unknown key `{key}` at line {}, column {col}: `{}`)",
                message.trim_end(),
                i + 1,
                lines[i].trim()
            )
        }
        None => message.to_string(),
    }
}

/// The key of an "unknown field `key`" message.
fn unknown_key(message: &str) -> Option<&str> {
    let rest = message.split_once("unknown field `")?.1;
    Some(&rest[..rest.find('`')?])
}

#[cfg(test)]
mod tests;
