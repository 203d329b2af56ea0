//! The Slurm array job of a campaign: `metabezier slurm SPEC --tasks N`
//! prints an `sbatch` script whose array task `i` runs shard `i + 1` of `N`
//! into its own `shard-K-of-N/` directory, with `--resume` so that a
//! requeued task continues where it stopped, and `--threads` from the CPUs
//! Slurm gave the task. `metabezier merge DIR` joins the shards afterwards.

use std::path::{Path, PathBuf};

use super::spec::Spec;

/// What the array job asks of Slurm.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SlurmOptions {
    /// Array tasks, one shard each.
    pub tasks: usize,
    /// The campaign's output directory; each shard writes beneath it.
    pub out: PathBuf,
    /// The time limit of each task (`--time`), as `[D-]HH:MM:SS`.
    pub time: Option<String>,
    /// CPUs per task (`--cpus-per-task`), which become the task's threads.
    pub cpus: Option<u16>,
    /// Further `sbatch` options (partition, account, ...), one `#SBATCH`
    /// line per option.
    pub sbatch: Option<String>,
    /// Run each task with `--allow-large`.
    pub allow_large: bool,
}

/// An array job that cannot be written as asked.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SlurmError {
    /// More tasks than runs, or none.
    #[error(
        "--tasks {tasks}: expected 1 to {runs} tasks (one shard each); the campaign {name} has {runs} runs"
    )]
    Tasks {
        /// The tasks asked for.
        tasks: usize,
        /// The runs of the campaign.
        runs: usize,
        /// The campaign's name.
        name: String,
    },
    /// A path that cannot be written into a shell script as it is: not
    /// UTF-8, or holding a control character (a newline would end the
    /// comment or the `#SBATCH` block and run as a command).
    #[error(
        "{what} \"{path}\": the path holds {problem}, which a job script cannot carry safely; rename it or choose another path"
    )]
    PathText {
        /// Which path (`--out`, the spec, the binary).
        what: &'static str,
        /// The path, with its control characters escaped.
        path: String,
        /// What is wrong, such as "a newline (U+000A) at character 12".
        problem: String,
    },
    /// A time limit that is not `[D-]HH:MM:SS`.
    #[error(
        "--time \"{0}\": expected a time limit per task as HH:MM:SS or D-HH:MM:SS, such as 02:30:00, with minutes and seconds below 60"
    )]
    Time(String),
    /// `--sbatch` text that does not start with an option.
    #[error(
        "--sbatch \"{text}\": expected sbatch options, each starting with '-', such as \"--partition=short --account=proj\"; found \"{word}\" before any option"
    )]
    SbatchSyntax {
        /// The whole text given.
        text: String,
        /// The word that is not an option's value.
        word: String,
    },
    /// `--sbatch` sets an option the script sets itself.
    #[error("--sbatch: {option} is set by metabezier slurm itself; use {instead}")]
    SbatchReserved {
        /// The option given.
        option: String,
        /// The `metabezier slurm` argument to use instead.
        instead: &'static str,
    },
}

/// The `sbatch` array script of `spec` (at the absolute path `spec_path`),
/// run by the binary `exe`: one shard per task, `--resume` so a requeued
/// task continues, and the `merge` command to run afterwards in a comment.
pub fn sbatch_script(
    spec: &Spec,
    spec_path: &Path,
    exe: &Path,
    opts: &SlurmOptions,
) -> Result<String, SlurmError> {
    let runs = usize::try_from(spec.run_count()).unwrap_or(usize::MAX);
    let n = opts.tasks;
    check_path("the spec", spec_path)?;
    check_path("--out", &opts.out)?;
    check_path("the metabezier binary", exe)?;
    if n == 0 || n > runs {
        return Err(SlurmError::Tasks {
            tasks: n,
            runs,
            name: spec.name.clone(),
        });
    }
    let mut directives = vec![
        format!("--job-name=metabezier-{}", spec.name),
        format!("--array=0-{}", n - 1),
        "--ntasks=1".to_owned(),
    ];
    if let Some(c) = opts.cpus {
        directives.push(format!("--cpus-per-task={c}"));
    }
    if let Some(t) = &opts.time {
        check_time(t)?;
        directives.push(format!("--time={t}"));
    }
    directives.push("--requeue".to_owned());
    directives.push("--open-mode=append".to_owned());
    directives.extend(sbatch_lines(opts.sbatch.as_deref().unwrap_or(""))?);

    let (exe, out) = (quote(exe), quote(&opts.out));
    let mut s = String::from("#!/bin/bash\n");
    s.push_str(&format!(
        "# Slurm array job of the campaign {} ({}): {runs} runs in {n} shards,\n\
         # one per array task. Written by `metabezier slurm`; submit it with\n\
         #   sbatch THIS_FILE\n\
         # Task i runs shard i+1/{n} into {}/shard-K-of-{n}/ with --resume, so a\n\
         # requeued or resubmitted task keeps the runs it finished. Its output goes\n\
         # to slurm-JOB_TASK.out in the submission directory.\n\
         # When every task has finished, join the shards:\n\
         #   {exe} merge {out} --spec {}\n",
        spec.name,
        spec_path.display(),
        opts.out.display(),
        quote(spec_path),
    ));
    for d in &directives {
        s.push_str(&format!("#SBATCH {d}\n"));
    }
    s.push_str("set -euo pipefail\n");
    // N is fixed here rather than taken from SLURM_ARRAY_TASK_COUNT, so that
    // resubmitting a subset of the tasks (sbatch --array=3) keeps the shards.
    s.push_str(&format!("shard=\"$((SLURM_ARRAY_TASK_ID + 1))/{n}\"\n"));
    s.push_str(&format!(
        "exec {exe} run {} --out {out} --shard \"$shard\" --threads \"${{SLURM_CPUS_PER_TASK:-1}}\" --resume --quiet{}\n",
        quote(spec_path),
        if opts.allow_large { " --allow-large" } else { "" }
    ));
    Ok(s)
}

/// Refuses a path the script cannot hold verbatim in its comments and
/// commands: one that is not UTF-8 or holds a control character.
fn check_path(what: &'static str, path: &Path) -> Result<(), SlurmError> {
    let refuse = |problem: String| SlurmError::PathText {
        what,
        path: path.to_string_lossy().escape_debug().to_string(),
        problem,
    };
    let Some(text) = path.to_str() else {
        return Err(refuse("bytes that are not UTF-8".into()));
    };
    match text.chars().enumerate().find(|(_, c)| c.is_control()) {
        Some((i, c)) => Err(refuse(format!(
            "a control character (U+{:04X}) at character {}",
            u32::from(c),
            i + 1
        ))),
        None => Ok(()),
    }
}

/// `path` as one word of a POSIX shell, in single quotes.
fn quote(path: &Path) -> String {
    format!("'{}'", path.display().to_string().replace('\'', r"'\''"))
}

/// Checks a time limit `[D-]HH:MM:SS`.
fn check_time(text: &str) -> Result<(), SlurmError> {
    let bad = || SlurmError::Time(text.to_owned());
    let digits = |s: &str| !s.is_empty() && s.len() <= 4 && s.bytes().all(|b| b.is_ascii_digit());
    let clock = match text.split_once('-') {
        Some((days, clock)) if digits(days) => clock,
        Some(_) => return Err(bad()),
        None => text,
    };
    let parts: Vec<&str> = clock.split(':').collect();
    let [h, m, s] = parts[..] else {
        return Err(bad());
    };
    let below_60 = |x: &str| x.len() == 2 && digits(x) && x < "60";
    if digits(h) && below_60(m) && below_60(s) {
        Ok(())
    } else {
        Err(bad())
    }
}

/// The `#SBATCH` lines of `--sbatch` text: each word starting with `-`
/// begins an option, and the words after it up to the next option are its
/// value (`-p short` and `--partition=short` both work).
fn sbatch_lines(text: &str) -> Result<Vec<String>, SlurmError> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        if word.starts_with('-') {
            if let Some(instead) = reserved(word) {
                return Err(SlurmError::SbatchReserved {
                    option: word.to_owned(),
                    instead,
                });
            }
            lines.push(word.to_owned());
        } else if let Some(last) = lines.last_mut() {
            last.push(' ');
            last.push_str(word);
        } else {
            return Err(SlurmError::SbatchSyntax {
                text: text.to_owned(),
                word: word.to_owned(),
            });
        }
    }
    Ok(lines)
}

/// The `metabezier slurm` argument that sets `option`, if the script sets it.
fn reserved(option: &str) -> Option<&'static str> {
    let name = option.split('=').next().unwrap_or(option);
    let long = |l: &str| name == l;
    let short = |s: &str| !option.starts_with("--") && option.starts_with(s);
    if long("--array") || short("-a") {
        Some("--tasks")
    } else if long("--cpus-per-task") || short("-c") {
        Some("--cpus")
    } else if long("--time") || short("-t") {
        Some("--time")
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_limits_are_checked() {
        for good in ["02:30:00", "0:05:00", "1-00:00:00", "100:00:59"] {
            assert_eq!(check_time(good), Ok(()), "{good}");
        }
        for bad in [
            "2:30",
            "02:60:00",
            "02:30:0",
            "x-01:00:00",
            "01:00:00-1",
            "",
            "1-",
        ] {
            assert_eq!(check_time(bad), Err(SlurmError::Time(bad.into())), "{bad}");
        }
    }

    #[test]
    fn sbatch_options_become_lines() {
        assert_eq!(
            sbatch_lines(" -p short  --account=proj --mem 4G ").unwrap(),
            ["-p short", "--account=proj", "--mem 4G"]
        );
        assert_eq!(sbatch_lines("").unwrap(), Vec::<String>::new());
        assert!(matches!(
            sbatch_lines("short -p x"),
            Err(SlurmError::SbatchSyntax { word, .. }) if word == "short"
        ));
        for (opt, instead) in [
            ("--array=1-3", "--tasks"),
            ("-a", "--tasks"),
            ("-c4", "--cpus"),
            ("--cpus-per-task=2", "--cpus"),
            ("--time=1:00:00", "--time"),
        ] {
            assert_eq!(
                sbatch_lines(opt),
                Err(SlurmError::SbatchReserved {
                    option: opt.into(),
                    instead
                })
            );
        }
        assert!(sbatch_lines("-A proj --constraint=avx2").is_ok());
    }

    #[test]
    fn paths_are_quoted_for_the_shell() {
        assert_eq!(quote(Path::new("/a b/it's")), r"'/a b/it'\''s'");
    }
}
