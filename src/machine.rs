//! What the machine has, read from the operating system's own files (not inputs): its memory,
//! for the bake's default patch and probe limits.

/// The machine's memory in bytes: physical RAM (`/proc/meminfo`), or the cgroup's limit when
/// lower; 8 GiB where neither can be read.
pub(crate) fn memory() -> f64 {
    let ram = std::fs::read_to_string("/proc/meminfo").ok().and_then(|t| {
        let line = t.lines().find(|l| l.starts_with("MemTotal:"))?;
        let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
        Some(kb * 1024.0)
    });
    let cgroup = std::fs::read_to_string("/sys/fs/cgroup/memory.max")
        .ok()
        .and_then(|t| t.trim().parse::<f64>().ok());
    match (ram, cgroup) {
        (Some(r), Some(c)) => r.min(c),
        (Some(r), None) => r,
        (None, Some(c)) => c,
        (None, None) => 8.0 * 1024.0 * 1024.0 * 1024.0,
    }
}
