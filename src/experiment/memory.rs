//! What the machine can hold: large allocations checked against the memory
//! available before they are made, so that a grid too large for this
//! machine is an error that says so instead of an abort mid-run.

/// Bytes of memory available for new allocations, where the platform tells
/// (Linux: `MemAvailable` in `/proc/meminfo`); `None` elsewhere, and then
/// only the fixed limits apply (e.g. `Grid::MAX_CELLS`).
pub(crate) fn available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_meminfo(&text)
}

/// `MemAvailable` of a `/proc/meminfo` text, in bytes.
fn parse_meminfo(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// An error message when `bytes` (needed for `what`) exceed what `available`
/// says the machine has.
pub(crate) fn check(what: &str, bytes: u64, available: Option<u64>) -> Result<(), String> {
    match available {
        Some(free) if bytes > free => Err(format!(
            "{what} needs about {} of memory and this machine has {} available",
            gib(bytes),
            gib(free)
        )),
        _ => Ok(()),
    }
}

fn gib(bytes: u64) -> String {
    format!("{:.1} GiB", bytes as f64 / f64::from(1u32 << 30))
}

#[cfg(test)]
mod tests {
    #[test]
    fn meminfo_is_read_and_large_needs_are_refused() {
        let text = "MemTotal:       24000000 kB\nMemFree:  100 kB\nMemAvailable:   2097152 kB\n";
        assert_eq!(super::parse_meminfo(text), Some(2 << 30));
        assert_eq!(super::parse_meminfo("MemTotal: 5 kB\n"), None);
        let err = super::check("the grid", 3 << 30, Some(2 << 30)).unwrap_err();
        assert!(err.contains("3.0 GiB") && err.contains("2.0 GiB"), "{err}");
        assert!(super::check("the grid", 1 << 30, Some(2 << 30)).is_ok());
        assert!(super::check("the grid", u64::MAX, None).is_ok());
    }
}
