//! Every config kind the binary reads, fed mutated and truncated TOML by a seeded mutator: a
//! mutation that must make the file invalid (an unknown key, a number turned into a string, a key
//! cut before its `=`) gives an error naming what is wrong and where, and no mutation at all makes
//! the parser or the validation that follows it panic.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{parse, with_key_position};

/// A config kind: its name and a check that parses and validates a text, returning the message the
/// user would see on failure.
struct ConfigKind {
    name: &'static str,
    check: fn(&str) -> Result<(), String>,
}

fn via<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, String> {
    parse::<T>(text, Path::new("mutated.toml")).map_err(|e| format!("{e:#}"))
}

fn kinds() -> Vec<ConfigKind> {
    use md_bridge::junction::JunctionConfig;
    use md_bridge::model::ModelConfig;
    use md_bridge::silica::junction::SilicaJunctionConfig;
    use md_bridge::silica::SilicaConfig;
    vec![
        ConfigKind {
            name: "patch",
            check: |t| via::<dem::scenario::patch::PatchSuite>(t).map(|_| ()),
        },
        ConfigKind {
            name: "sample",
            check: |t| via::<crate::cmd_patch::SampleConfig>(t).map(|_| ()),
        },
        ConfigKind {
            name: "calibrate",
            check: |t| {
                let cfg = calibrate::CalibrationConfig::from_toml(t)
                    .map_err(|e| with_key_position(t, &e.to_string()))?;
                cfg.prepare().map(|_| ()).map_err(|e| e.to_string())
            },
        },
        ConfigKind {
            name: "junction",
            check: |t| {
                let f = via::<validation::wear::junction::JunctionFile>(t)?;
                f.resolve(&configs_dir())
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            },
        },
        ConfigKind {
            name: "sliding",
            check: |t| {
                via::<validation::wear::sliding::SlidingFile>(t)?
                    .runs()
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            },
        },
        ConfigKind {
            name: "dstar",
            check: |t| {
                let f = via::<validation::wear::dstar::DstarFile>(t)?;
                f.resolve(&configs_dir())
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            },
        },
        ConfigKind {
            name: "compare",
            check: |t| {
                via::<validation::compare::CompareFile>(t)?
                    .validate()
                    .map_err(|e| e.to_string())
            },
        },
        ConfigKind {
            name: "impact",
            check: |t| {
                let mut f = via::<dem::scenario::plastic::ImpactFile>(t)?;
                // Landing points multiply the jobs without adding a value to validate; a mutated
                // `aims = 16999` would only cost memory here.
                if let Some(s) = f.sweep.as_mut() {
                    s.aims = s.aims.min(1);
                }
                f.jobs().map(|_| ()).map_err(|e| e.to_string())
            },
        },
        ConfigKind {
            name: "scratch",
            check: |t| {
                via::<dem::scenario::plastic::ScratchFile>(t)?
                    .tests()
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            },
        },
        ConfigKind {
            name: "md silica",
            check: |t| {
                via::<SilicaConfig>(t)?
                    .validate()
                    .map_err(|e| e.to_string())
            },
        },
        ConfigKind {
            name: "md model",
            check: |t| via::<ModelConfig>(t)?.validate().map_err(|e| e.to_string()),
        },
        ConfigKind {
            name: "md junction",
            check: |t| {
                via::<JunctionConfig>(t)?
                    .validate()
                    .map_err(|e| e.to_string())
            },
        },
        ConfigKind {
            name: "md silica-junction",
            check: |t| {
                via::<SilicaJunctionConfig>(t)?
                    .validate()
                    .map_err(|e| e.to_string())
            },
        },
    ]
}

fn configs_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../configs")
}

/// Valid texts of each kind: the shipped configs, and the MD defaults written out.
fn seeds(kind: &str) -> Vec<(String, String)> {
    use md_bridge::junction::JunctionConfig;
    use md_bridge::model::ModelConfig;
    use md_bridge::silica::junction::SilicaJunctionConfig;
    use md_bridge::silica::SilicaConfig;
    let prefix = match kind {
        "patch" => "patch-",
        "sample" => "sample-",
        "calibrate" => "calibrate-",
        "md silica" => "silica-",
        "junction" => "junction-",
        "dstar" => "dstar-",
        "compare" => "compare-",
        "impact" => "impact-",
        "scratch" => "scratch",
        "sliding" => "sliding-",
        _ => "\0",
    };
    let mut out: Vec<(String, String)> = std::fs::read_dir(configs_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap().to_string_lossy().starts_with(prefix))
        .map(|p| {
            (
                p.display().to_string(),
                std::fs::read_to_string(&p).unwrap(),
            )
        })
        .collect();
    let default = match kind {
        "md silica" => toml::to_string(&SilicaConfig::default()),
        "md model" => toml::to_string(&ModelConfig::default()),
        "md junction" => toml::to_string(&JunctionConfig::default()),
        "md silica-junction" => toml::to_string(&SilicaJunctionConfig::default()),
        _ => Ok(String::new()),
    }
    .unwrap();
    if !default.is_empty() {
        out.push((format!("{kind} defaults"), default));
    }
    out.sort();
    out
}

/// Runs `check` and turns a panic into a test failure naming the input.
fn no_panic(kind: &ConfigKind, what: &str, text: &str) -> Result<(), String> {
    catch_unwind(AssertUnwindSafe(|| (kind.check)(text)))
        .unwrap_or_else(|_| panic!("{} config panicked on {what}:\n{text}", kind.name))
}

/// Line indices after which a new `key = value` line lands in a table (not inside a multi-line
/// array or string).
fn insertion_points(text: &str) -> Vec<usize> {
    let mut depth = 0i32;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let code = line.split('#').next().unwrap_or("");
        let is_header = code.trim_start().starts_with('[') && depth == 0;
        if !is_header {
            depth += code.matches('[').count() as i32 - code.matches(']').count() as i32;
        }
        if depth == 0 && !code.contains("\"\"\"") {
            out.push(i);
        }
    }
    out
}

/// Lines `key = <number>` outside arrays: (line index, key).
fn number_lines(text: &str) -> Vec<(usize, String)> {
    text.lines()
        .enumerate()
        .filter_map(|(i, l)| {
            // A comment may hold `D = 35`: not a key.
            if l.trim_start().starts_with('#') {
                return None;
            }
            let (k, v) = l.split_once('=')?;
            let v = v.split('#').next()?.trim();
            (v.parse::<f64>().is_ok() && !k.contains('[')).then(|| (i, k.trim().to_string()))
        })
        .collect()
}

fn with_line(text: &str, at: usize, new: &str, replace: bool) -> String {
    let mut lines: Vec<&str> = text.lines().collect();
    if replace {
        lines[at] = new;
    } else {
        lines.insert(at + 1, new);
    }
    lines.join("\n") + "\n"
}

#[test]
fn every_kind_has_valid_seeds() {
    for kind in kinds() {
        let seeds = seeds(kind.name);
        assert!(!seeds.is_empty(), "no config of kind {}", kind.name);
        for (name, text) in seeds {
            // Shipped configs may name files (samples, cards) that a fresh clone lacks: parse only.
            let res = no_panic(&kind, &name, &text);
            if let Err(e) = res {
                assert!(
                    !e.contains("TOML parse error") && !e.contains("unknown field"),
                    "{name} does not parse: {e}"
                );
            }
        }
    }
}

#[test]
fn unknown_keys_are_refused_with_their_name_and_line() {
    let mut rng = ChaCha8Rng::seed_from_u64(18);
    let mut checked = 0;
    for kind in kinds() {
        for (name, text) in seeds(kind.name) {
            let points = insertion_points(&text);
            for _ in 0..12 {
                let at = points[rng.gen_range(0..points.len())];
                let key = format!("zz_unknown_{}", rng.gen_range(0..1000));
                let mutated = with_line(&text, at, &format!("{key} = 1"), false);
                let err = no_panic(&kind, &name, &mutated).expect_err(&format!(
                    "{}: `{key}` at line {} accepted:\n{mutated}",
                    kind.name,
                    at + 2
                ));
                let line = format!("line {}", at + 2);
                assert!(
                    err.contains(&key) && err.contains(&line),
                    "{} ({name}): the error does not say `{key}` and `{line}`:\n{err}\n--- input:\n{mutated}",
                    kind.name
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 100, "{checked}");
}

#[test]
fn wrong_types_and_cut_keys_are_errors() {
    let mut rng = ChaCha8Rng::seed_from_u64(1818);
    for kind in kinds() {
        for (name, text) in seeds(kind.name) {
            let nums = number_lines(&text);
            for _ in 0..8 {
                if nums.is_empty() {
                    break;
                }
                let (i, key) = &nums[rng.gen_range(0..nums.len())];
                let flipped = with_line(&text, *i, &format!("{key} = \"not a number\""), true);
                let err = no_panic(&kind, &name, &flipped).expect_err(&format!(
                    "{}: `{key}` as a string accepted:\n{flipped}",
                    kind.name
                ));
                assert!(
                    err.contains("invalid type") || err.contains("expected"),
                    "{err}"
                );
                // Truncated inside the line: the key without its `=`.
                let lines: Vec<&str> = text.lines().collect();
                let cut: String = lines[..*i]
                    .iter()
                    .map(|l| format!("{l}\n"))
                    .collect::<String>()
                    + key;
                let err = no_panic(&kind, &name, &cut)
                    .expect_err(&format!("{}: file cut after `{key}` accepted", kind.name));
                assert!(err.contains("TOML parse error"), "{err}");
            }
        }
    }
}

#[test]
fn random_mutations_and_truncations_never_panic() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let alphabet: Vec<char> = "[]{}=\"'.,#-+_ \n0123456789eEaz".chars().collect();
    let mut errors = 0;
    let mut total = 0;
    for kind in kinds() {
        for (name, text) in seeds(kind.name) {
            let chars: Vec<char> = text.chars().collect();
            for round in 0..150 {
                let mut m = chars.clone();
                for _ in 0..rng.gen_range(1..4) {
                    let at = rng.gen_range(0..m.len().max(1));
                    let c = alphabet[rng.gen_range(0..alphabet.len())];
                    let last = m.len().saturating_sub(1);
                    match rng.gen_range(0..4) {
                        0 if !m.is_empty() => {
                            m.remove(at.min(last));
                        }
                        1 if !m.is_empty() => m[at.min(last)] = c,
                        2 => m.insert(at.min(m.len()), c),
                        _ => m.truncate(at),
                    }
                }
                let mutated: String = m.into_iter().collect();
                total += 1;
                if no_panic(&kind, &format!("{name} mutation {round}"), &mutated).is_err() {
                    errors += 1;
                }
            }
        }
    }
    // Most random edits break the file; the point is that none panicked.
    assert!(errors * 2 > total, "{errors} errors in {total} mutations");
}
