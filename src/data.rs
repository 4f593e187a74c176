//! Reference tables embedded in the binary, each CSV with its `#` source
//! lines (see `data/README.md`), and a reader for them.

pub const CMF_1931: &str = include_str!("../data/cie1931_2deg_cmf.csv");
pub const D65: &str = include_str!("../data/cie_d65.csv");
pub const FL: &str = include_str!("../data/cie_fl.csv");
pub const FL3: &str = include_str!("../data/cie_fl3.csv");
pub const GLASSES: &str = include_str!("../data/glasses.csv");
/// The CFL's line positions with their sources (what `cfl_model.csv` is fitted at).
#[cfg(test)]
pub const CFL_LINES: &str = include_str!("../data/cfl_lines.csv");
pub const CFL_MODEL: &str = include_str!("../data/cfl_model.csv");
/// The line designations behind `optics::glass::lines` (checked by a test).
#[cfg(test)]
pub const FRAUNHOFER: &str = include_str!("../data/fraunhofer_lines.csv");

/// The most bytes one input file may hold: 2 GiB, or what the environment
/// variable `REFRACT_MAX_INPUT_BYTES` says (for bigger meshes).
pub fn max_input_bytes() -> u64 {
    std::env::var("REFRACT_MAX_INPUT_BYTES").ok().and_then(|v| v.trim().parse().ok()).unwrap_or(2 << 30)
}

/// Memory a run may still take, in bytes, and what limits it (for the
/// message, `{}` standing for the amount): the smallest of what the environment variable
/// `REFRACT_AVAILABLE_MEMORY` says (to leave room for others on a shared
/// machine), Linux's MemAvailable, the process's limits (RLIMIT_AS less
/// the address space in use, RLIMIT_DATA less the data in use), and the
/// cgroup's (a container's) `memory.max - memory.current` (cgroup v2) or
/// `memory.limit_in_bytes - memory.usage_in_bytes` (v1), over the cgroup
/// and its parents; `None` where none can be read, and then nothing is
/// checked.
pub fn available_memory() -> Option<(u64, String)> {
    tightest(memory_limits())
}

/// The least of the limits, with its name.
fn tightest(limits: Vec<(u64, String)>) -> Option<(u64, String)> {
    limits.into_iter().min_by_key(|(b, _)| *b)
}

fn memory_limits() -> Vec<(u64, String)> {
    let mut out = Vec::new();
    if let Some(v) = std::env::var("REFRACT_AVAILABLE_MEMORY").ok().and_then(|v| v.trim().parse().ok()) {
        out.push((v, "REFRACT_AVAILABLE_MEMORY allows {}".to_string()));
    }
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let kb_field =
        |text: &str, key: &str| -> Option<u64> { text.lines().find(|l| l.starts_with(key))?.split_whitespace().nth(1)?.parse::<u64>().ok().map(|k| k * 1024) };
    if let Some(free) = read("/proc/meminfo").and_then(|t| kb_field(&t, "MemAvailable:")) {
        out.push((free, "this machine has {} free (MemAvailable)".to_string()));
    }
    #[cfg(unix)]
    {
        let status = read("/proc/self/status").unwrap_or_default();
        for (res, field, how) in [
            (libc::RLIMIT_AS, "VmSize:", "address-space limit (RLIMIT_AS, `ulimit -v`)"),
            (libc::RLIMIT_DATA, "VmData:", "data-size limit (RLIMIT_DATA, `ulimit -d`)"),
        ] {
            let mut lim = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
            // SAFETY: getrlimit writes one rlimit into `lim`.
            if unsafe { libc::getrlimit(res, &mut lim) } == 0 && lim.rlim_cur != libc::RLIM_INFINITY {
                let used = kb_field(&status, field).unwrap_or(0);
                // rlim_t is u64 on Linux but not on every unix.
                #[allow(clippy::unnecessary_cast)]
                out.push(((lim.rlim_cur as u64).saturating_sub(used), format!("the process's {how} leaves {{}}")));
            }
        }
    }
    if let Some(c) = cgroup_room() {
        out.push(c);
    }
    out
}

/// The room left in this process's memory cgroup and its parents (the
/// tightest), if any has a limit.
fn cgroup_room() -> Option<(u64, String)> {
    cgroup_room_in(&std::fs::read_to_string("/proc/self/cgroup").ok()?, std::path::Path::new("/sys/fs/cgroup"))
}

/// `cgroup_room` for the cgroups listed in `cgroups` (as /proc/self/cgroup
/// lists them) under the cgroup file system mounted at `mount`.
fn cgroup_room_in(cgroups: &str, mount: &std::path::Path) -> Option<(u64, String)> {
    let num = |p: &std::path::Path| std::fs::read_to_string(p).ok().and_then(|t| t.trim().parse::<u64>().ok());
    let mut best: Option<(u64, String)> = None;
    for line in cgroups.lines() {
        let mut f = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) = (f.next(), f.next(), f.next()) else { continue };
        let (root, max, current, what) = if controllers.is_empty() {
            (mount.to_path_buf(), "memory.max", "memory.current", "memory.max - memory.current")
        } else if controllers.split(',').any(|c| c == "memory") {
            (mount.join("memory"), "memory.limit_in_bytes", "memory.usage_in_bytes", "memory.limit_in_bytes - memory.usage_in_bytes")
        } else {
            continue;
        };
        let root = root.as_os_str();
        // From the cgroup up to the root (inside a container the cgroup's
        // own folder is often the mount's root).
        let mut dir = std::path::PathBuf::from(root).join(path.trim_start_matches('/'));
        loop {
            if let (Some(m), Some(c)) = (num(&dir.join(max)), num(&dir.join(current))) {
                // Values near 2^63 mean "no limit".
                if m < 1 << 60 && best.as_ref().is_none_or(|b| m.saturating_sub(c) < b.0) {
                    best = Some((m.saturating_sub(c), format!("the cgroup's limit ({what} in {}) leaves {{}}", dir.display())));
                }
            }
            if dir.as_os_str().len() <= root.len() || !dir.pop() {
                break;
            }
        }
    }
    best
}

/// A run that would need more memory than the machine has free.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{what} would need about {} of memory; {}", size_text(*.need), .limit.replace("{}", &size_text(*.free)))]
pub struct MemoryError {
    /// What takes the memory, as a flag or a file's key would name it.
    pub what: String,
    pub need: u64,
    pub free: u64,
    /// Which limit, with `{}` where the free bytes go.
    pub limit: String,
}

/// Bytes as MiB or, from 100 MiB, GiB, to one decimal.
fn size_text(b: u64) -> String {
    if b >= 100 << 20 {
        format!("{:.1} GiB", b as f64 / (1u64 << 30) as f64)
    } else {
        format!("{:.1} MiB", b as f64 / (1u64 << 20) as f64)
    }
}

/// Refuses, before any work, a run whose estimated `need` (bytes) is more
/// than the machine has free; `what` says what takes the memory, as a
/// flag would name it.
pub fn check_memory(need: u64, what: &str) -> Result<(), MemoryError> {
    check_memory_against(need, available_memory(), what)
}

fn check_memory_against(need: u64, free: Option<(u64, String)>, what: &str) -> Result<(), MemoryError> {
    match free {
        Some((free, limit)) if need > free => Err(MemoryError { what: what.to_string(), need, free, limit }),
        _ => Ok(()),
    }
}

/// An output path where something other than a regular file stands.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{} is not a regular file (a folder, link, device or FIFO); refract replaces only regular files", .0.display())]
pub struct NotRegularFile(pub std::path::PathBuf);

/// Checks, before any work, that an output `path` is absent or a regular
/// file: an output replaces only regular files, never a folder, a link, a
/// device or a FIFO (the outputs' side of `read_input`).
pub fn check_regular(path: &std::path::Path) -> Result<(), NotRegularFile> {
    if std::fs::symlink_metadata(path).is_ok_and(|m| !m.is_file()) {
        return Err(NotRegularFile(path.to_path_buf()));
    }
    Ok(())
}

/// Reads an input file (a mesh, a scene or an experiment): only a regular
/// file, and no more than `max_input_bytes`, so a device or a FIFO named
/// by mistake cannot be read until memory runs out.
pub fn read_input(path: &std::path::Path) -> std::io::Result<Vec<u8>> {
    let cap = max_input_bytes();
    read_capped(path, cap, &format!("larger than the {cap}-byte limit on inputs (set REFRACT_MAX_INPUT_BYTES to raise it)"))
}

/// The most bytes a scene or experiment file may hold: 1 MiB. They are a
/// page of TOML; a bigger one is a mistake, and parsing a TOML table
/// takes several times its size in memory.
pub const MAX_SETTINGS_BYTES: u64 = 1 << 20;

/// Reads a scene or experiment file (`read_input` with the
/// `MAX_SETTINGS_BYTES` cap) as UTF-8 text.
pub fn read_settings_text(path: &std::path::Path) -> std::io::Result<String> {
    let bytes = read_capped(path, MAX_SETTINGS_BYTES, &format!("larger than the {MAX_SETTINGS_BYTES}-byte limit on scene and experiment files"))?;
    String::from_utf8(bytes).map_err(|_| std::io::Error::new(std::io::ErrorKind::InvalidData, "not UTF-8 text"))
}

fn read_capped(path: &std::path::Path, cap: u64, too_big_text: &str) -> std::io::Result<Vec<u8>> {
    use std::io::{Error, ErrorKind, Read};
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(Error::new(ErrorKind::InvalidInput, "not a regular file (a folder, device or FIFO); refract reads only regular files"));
    }
    let too_big = || Error::new(ErrorKind::InvalidInput, too_big_text.to_string());
    if meta.len() > cap {
        return Err(too_big());
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)?.take(cap + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > cap {
        return Err(too_big());
    }
    Ok(bytes)
}

/// `read_input` as UTF-8 text.
pub fn read_input_text(path: &std::path::Path) -> std::io::Result<String> {
    String::from_utf8(read_input(path)?).map_err(|_| std::io::Error::new(std::io::ErrorKind::InvalidData, "not UTF-8 text"))
}

/// A CSV table with `#` comment lines: its header and rows of fields.
pub struct Table {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// Parses embedded CSV text. The tables are part of the build, so a
    /// malformed one is a programming error caught by the unit tests.
    pub fn parse(text: &str) -> Table {
        let mut r = csv::ReaderBuilder::new().comment(Some(b'#')).flexible(true).from_reader(text.as_bytes());
        let header = r.headers().expect("embedded table has a header").iter().map(str::to_string).collect();
        let rows = r.records().map(|rec| rec.expect("embedded table parses").iter().map(|s| s.trim().to_string()).collect()).collect();
        Table { header, rows }
    }

    pub fn column(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }

    /// Column `name` as numbers (NaN where a cell is not a number).
    pub fn numbers(&self, name: &str) -> Option<Vec<f64>> {
        let c = self.column(name)?;
        Some(self.rows.iter().map(|r| r.get(c).and_then(|v| v.parse().ok()).unwrap_or(f64::NAN)).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_embedded_table_parses_with_numbers() {
        let cmf = Table::parse(CMF_1931);
        assert_eq!(cmf.rows.len(), 471);
        assert!(cmf.numbers("ybar").unwrap().iter().all(|v| v.is_finite()));
        assert_eq!(Table::parse(D65).rows.len(), 97);
        assert_eq!(Table::parse(FL).header.len(), 13);
        assert_eq!(Table::parse(FL3).header.len(), 16);
        assert_eq!(Table::parse(GLASSES).rows.len(), 9);
        assert!(Table::parse(CFL_LINES).numbers("wavelength_nm").unwrap().iter().all(|v| (400.0..720.0).contains(v)));
        assert!(Table::parse(FRAUNHOFER).rows.len() > 20);
    }
}

#[cfg(test)]
mod memory_tests {
    use super::*;

    #[test]
    fn a_run_bigger_than_free_memory_is_refused_by_name() {
        let free = |b: u64| Some((b, "this machine has {} free (MemAvailable)".to_string()));
        assert_eq!(
            check_memory_against(40 << 30, free(20 << 30), "--photons 2000000000").unwrap_err().to_string(),
            "--photons 2000000000 would need about 40.0 GiB of memory; this machine has 20.0 GiB free (MemAvailable)"
        );
        assert!(check_memory_against(1 << 30, free(20 << 30), "x").is_ok());
        assert!(check_memory_against(u64::MAX, None, "x").is_ok());
    }

    /// A container's or a Slurm job's cgroup (v2: memory.max, v1:
    /// memory.limit_in_bytes), and its parents': the least room is named;
    /// "max" and values near 2^63 are no limit.
    #[test]
    fn the_cgroup_with_the_least_room_is_named() {
        let mount = tempfile::tempdir().unwrap();
        let put = |dir: &str, files: &[(&str, &str)]| {
            let d = mount.path().join(dir);
            std::fs::create_dir_all(&d).unwrap();
            for (f, v) in files {
                std::fs::write(d.join(f), v).unwrap();
            }
        };
        put("job", &[("memory.max", "3000000000\n"), ("memory.current", "1000000000\n")]);
        put("job/step", &[("memory.max", "max\n"), ("memory.current", "10\n")]);
        let (room, name) = cgroup_room_in("0::/job/step\n", mount.path()).unwrap();
        assert_eq!(room, 2_000_000_000);
        assert!(name.starts_with("the cgroup's limit (memory.max - memory.current in ") && name.ends_with("job) leaves {}"), "{name}");
        put("memory/box", &[("memory.limit_in_bytes", "500000000"), ("memory.usage_in_bytes", "100000000")]);
        put("memory", &[("memory.limit_in_bytes", "9223372036854771712"), ("memory.usage_in_bytes", "5")]);
        let (room, name) = cgroup_room_in("4:memory:/box\n1:cpu:/\n", mount.path()).unwrap();
        assert_eq!(room, 400_000_000);
        assert!(name.contains("memory.limit_in_bytes - memory.usage_in_bytes in "), "{name}");
        assert_eq!(cgroup_room_in("0::/job/step\n", &mount.path().join("none")), None);
    }

    #[test]
    fn the_tightest_limit_is_the_one_named() {
        // One reading of the limits (free memory changes between two).
        let all = memory_limits();
        let (least, name) = tightest(all.clone()).unwrap();
        assert!(all.iter().all(|(b, _)| *b >= least) && all.iter().any(|(b, n)| *b == least && *n == name), "{all:?}");
        assert!(all.iter().any(|(_, n)| n.contains("MemAvailable")), "{all:?}");
    }
}
