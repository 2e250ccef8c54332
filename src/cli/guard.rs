//! What keeps a run from losing or mixing up data: the output folder is
//! checked before any work, no output may be one of the run's inputs,
//! Ctrl-C and SIGTERM stop cleanly, and a second one never cuts the result
//! files in half.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, LazyLock, Once};

use super::CliError;

/// Set by the first Ctrl-C or SIGTERM; shared with the optimizers, which
/// poll it while they evaluate.
static INTERRUPTED: LazyLock<Arc<AtomicBool>> = LazyLock::new(|| Arc::new(AtomicBool::new(false)));
static WRITING: AtomicBool = AtomicBool::new(false);
/// What the first Ctrl-C prints: what stopping means for the command.
static STOPPING: std::sync::Mutex<&str> = std::sync::Mutex::new(
    "stopping; the generation in progress is dropped (Ctrl-C again to quit at once)",
);

/// Sets what the first Ctrl-C prints (by default, what it means for a run).
pub(super) fn on_interrupt_say(note: &'static str) {
    *STOPPING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner) = note;
}

/// Makes Ctrl-C (and SIGTERM) stop the run cleanly within one evaluation:
/// the generation in progress is dropped and the results of the last
/// complete one are written; a second one quits at once, except while
/// result files are being written, which it lets finish.
/// Installed once per process.
pub(super) fn catch_interrupts() {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        let installed = ctrlc::set_handler(|| {
            if INTERRUPTED.swap(true, Ordering::SeqCst) {
                if WRITING.load(Ordering::SeqCst) {
                    errln!("\nshapegen: writing the results; quitting when they are complete");
                    return;
                }
                std::process::exit(130);
            }
            let note = *STOPPING
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            errln!("\nshapegen: {note}");
        });
        if let Err(e) = installed {
            errln!("shapegen: warning: cannot catch Ctrl-C: {e}");
        }
    });
}

/// The flag Ctrl-C (or SIGTERM) sets, for [`Interruptible`](crate::optimize::Interruptible).
pub(super) fn interrupt_flag() -> Arc<AtomicBool> {
    Arc::clone(&INTERRUPTED)
}

/// Whether Ctrl-C (or SIGTERM) was received.
pub(super) fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// Runs `write` (writing result files) with a second Ctrl-C held off until
/// it returns, so the files are never half of two runs.
pub(super) fn writing<T>(write: impl FnOnce() -> T) -> T {
    WRITING.store(true, Ordering::SeqCst);
    let out = write();
    WRITING.store(false, Ordering::SeqCst);
    out
}

/// Creates `dir` if needed and checks that files can be written there (a
/// probe file is created and removed), so that a run never computes
/// results it cannot save.
pub(super) fn check_output_dir(dir: &Path) -> Result<(), CliError> {
    let fail = |why: String| {
        CliError::msg(format!(
            "cannot write results to {}: {why}; nothing was run",
            dir.display()
        ))
    };
    if dir.exists() && !dir.is_dir() {
        return Err(fail("it is not a directory".into()));
    }
    std::fs::create_dir_all(dir).map_err(|e| fail(e.to_string()))?;
    let probe = dir.join(format!(".shapegen-probe-{}", std::process::id()));
    std::fs::write(&probe, b"probe").map_err(|e| fail(e.to_string()))?;
    std::fs::remove_file(&probe).map_err(|e| fail(e.to_string()))?;
    Ok(())
}

/// An output folder taken by this process: a second shapegen on the same
/// folder is refused until it is dropped (an advisory lock on
/// `.shapegen.lock` in the folder, which the operating system releases
/// even if the process is killed).
#[must_use = "the folder is free again when the lock is dropped"]
pub(super) struct OutputLock {
    file: std::fs::File,
    path: PathBuf,
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still held: a process that opened it before is
        // refused by the lock, one that opens it after makes a new one.
        std::fs::remove_file(&self.path).ok();
        self.file.unlock().ok();
    }
}

/// [`check_output_dir`], then takes the folder for this run: a second run
/// on it (in this or another process) is refused before it starts, naming
/// the first.
pub(super) fn take_output_dir(dir: &Path) -> Result<OutputLock, CliError> {
    use std::io::{Read as _, Seek as _, Write as _};
    check_output_dir(dir)?;
    let path = dir.join(".shapegen.lock");
    let fail = |e: std::io::Error| {
        CliError::msg(format!(
            "cannot take {} for this run: {e}; nothing was run",
            dir.display()
        ))
    };
    let mut file = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .read(true)
        .write(true)
        .open(&path)
        .map_err(fail)?;
    match file.try_lock() {
        Ok(()) => {}
        Err(std::fs::TryLockError::WouldBlock) => {
            let mut holder = String::new();
            file.read_to_string(&mut holder).ok();
            let holder = holder.trim();
            return Err(CliError::msg(format!(
                "another shapegen is writing to {} ({}): wait for it to end or choose another --out; nothing was run",
                dir.display(),
                if holder.is_empty() {
                    "it has just started"
                } else {
                    holder
                }
            )));
        }
        Err(std::fs::TryLockError::Error(e)) => return Err(fail(e)),
    }
    let command: Vec<String> = std::env::args().collect();
    file.set_len(0).map_err(fail)?;
    file.rewind().map_err(fail)?;
    write!(
        file,
        "process {}: {}",
        std::process::id(),
        command.join(" ")
    )
    .map_err(fail)?;
    Ok(OutputLock { file, path })
}

/// Checks that a file to be written can be, before a run: its folder exists
/// and takes a probe file.
pub(super) fn check_output_file(path: &Path) -> Result<(), CliError> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if path.is_dir() {
        return Err(CliError::msg(format!(
            "cannot write {}: it is a directory",
            path.display()
        )));
    }
    check_output_dir(&dir)
}

/// Refuses outputs that are inputs of the run: each of `outputs` (files
/// about to be written) against each of `inputs` (files read), compared as
/// canonical paths.
pub(super) fn refuse_overwriting_inputs(
    outputs: &[PathBuf],
    inputs: &[PathBuf],
) -> Result<(), CliError> {
    let canonical = |p: &Path| std::fs::canonicalize(p).ok();
    let inputs: Vec<(PathBuf, PathBuf)> = inputs
        .iter()
        .filter_map(|p| canonical(p).map(|c| (p.clone(), c)))
        .collect();
    for out in outputs {
        let Some(c) = canonical(out) else { continue };
        if let Some((input, _)) = inputs.iter().find(|(_, i)| *i == c) {
            return Err(CliError::msg(format!(
                "the run would write {} over its input {}: choose another --out or --checkpoint; nothing was run",
                out.display(),
                input.display()
            )));
        }
    }
    Ok(())
}
