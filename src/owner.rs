//! Who this process is, so that a file it leaves (a folder's lock, a
//! temporary file) can be told apart from another program's, and its
//! owner proved gone before the file is taken over or removed.
//!
//! A process is named by its host name (for messages), the kernel's boot
//! id and pid namespace (which processes it can see), its pid and its
//! start time in clock ticks since boot (`/proc/PID/stat`, field 22: a pid
//! reused by a later process has a later start). An owner is provably gone
//! only when it shares this process's boot and pid namespace and no
//! process with its pid and start time exists; an owner this process cannot
//! see (another host, container or pid namespace, or a file it cannot
//! read) is never taken for gone.

use std::path::Path;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Owner {
    pub host: String,
    /// `/proc/sys/kernel/random/boot_id` (empty where there is none).
    pub boot: String,
    /// The pid namespace's inode (`/proc/self/ns/pid`), 0 where unknown.
    pub pidns: u64,
    pub pid: u32,
    /// Clock ticks after boot at which the process started (0 where unknown).
    pub start: u64,
}

fn read(p: &str) -> String {
    std::fs::read_to_string(p).unwrap_or_default().trim().to_string()
}

/// The start time (field 22 of `/proc/PID/stat`) of a process, if it is
/// there. The command name (field 2) may hold spaces and brackets, so the
/// fields are counted after its closing bracket.
fn start_ticks(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let after = &stat[stat.rfind(')')? + 1..];
    after.split_whitespace().nth(19)?.parse().ok()
}

impl Owner {
    /// This process (read once).
    pub fn me() -> Owner {
        static ME: std::sync::OnceLock<Owner> = std::sync::OnceLock::new();
        ME.get_or_init(Owner::read_me).clone()
    }

    fn read_me() -> Owner {
        let pid = std::process::id();
        let pidns = std::fs::read_link("/proc/self/ns/pid")
            .ok()
            .and_then(|l| l.to_string_lossy().trim_start_matches("pid:[").trim_end_matches(']').parse().ok())
            .unwrap_or(0);
        Owner { host: read("/proc/sys/kernel/hostname"), boot: read("/proc/sys/kernel/random/boot_id"), pidns, pid, start: start_ticks(pid).unwrap_or(0) }
    }

    /// Whether `other` runs where this process can see it: the same boot
    /// of the same kernel and the same pid namespace, each known.
    pub fn sees(&self, other: &Owner) -> bool {
        !self.boot.is_empty() && self.boot == other.boot && self.pidns != 0 && self.pidns == other.pidns
    }

    /// Whether this owner is provably gone, as seen from `me`: visible to
    /// `me`, and no process with its pid started at its start time.
    pub fn gone(&self, me: &Owner) -> bool {
        if !me.sees(self) || self.start == 0 {
            return false;
        }
        if self.pid == me.pid {
            return self.start != me.start;
        }
        match start_ticks(self.pid) {
            None => !Path::new(&format!("/proc/{}", self.pid)).exists(),
            Some(t) => t != self.start,
        }
    }

    /// A short token naming this owner in a file name:
    /// `rf-PID-START-PIDNS-BOOT8` (hex pid namespace, the boot id's first
    /// 8 hex digits).
    pub fn token(&self) -> String {
        let boot: String = self.boot.chars().filter(char::is_ascii_hexdigit).take(8).collect();
        format!("rf-{}-{}-{:x}-{boot}", self.pid, self.start, self.pidns)
    }

    /// The owner a `token` names (host unknown), if it is one.
    pub fn from_token(token: &str) -> Option<Owner> {
        let mut f = token.strip_prefix("rf-")?.split('-');
        let pid = f.next()?.parse().ok()?;
        let start = f.next()?.parse().ok()?;
        let pidns = u64::from_str_radix(f.next()?, 16).ok()?;
        let boot = f.next()?.to_string();
        if f.next().is_some() || boot.len() != 8 || !boot.chars().all(|c| c.is_ascii_hexdigit()) {
            return None;
        }
        Some(Owner { host: String::new(), boot, pidns, pid, start })
    }

    /// Whether a token's owner is provably gone: the token's boot prefix
    /// must match this boot's.
    pub fn token_gone(token: &str, me: &Owner) -> bool {
        let Some(mut o) = Owner::from_token(token) else { return false };
        if !me.boot.starts_with(&o.boot) {
            return false;
        }
        o.boot = me.boot.clone();
        o.gone(me)
    }
}

/// 64 random bits from the system (`/dev/urandom`), or, where it cannot be
/// read, from the clock, pid and an address (unique enough for a token).
pub fn random_u64() -> u64 {
    use std::io::Read;
    let mut b = [0u8; 8];
    if std::fs::File::open("/dev/urandom").and_then(|mut f| f.read_exact(&mut b)).is_ok() {
        return u64::from_le_bytes(b);
    }
    let t = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos() as u64);
    let here = &b as *const _ as u64;
    // SplitMix64's finaliser (Steele et al. 2014) mixes the three.
    let mut z = t ^ (std::process::id() as u64).rotate_left(32) ^ here;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn this_process_is_alive_and_a_reused_pid_is_not_its_owner() {
        let me = Owner::me();
        assert!(me.start > 0 && me.pidns != 0 && !me.boot.is_empty(), "{me:?}");
        assert!(!me.gone(&me));
        // Same pid, another start time: a later process with a reused pid.
        assert!(Owner { start: me.start + 1, ..me.clone() }.gone(&me));
        // Pid 1 is alive, but not the owner whose start time is another.
        let init = start_ticks(1).unwrap();
        assert!(!Owner { pid: 1, start: init, ..me.clone() }.gone(&me));
        assert!(Owner { pid: 1, start: init + 7, ..me.clone() }.gone(&me));
        // An owner in another pid namespace or boot cannot be seen: never gone.
        assert!(!Owner { pidns: me.pidns + 1, pid: 4_000_000, ..me.clone() }.gone(&me));
        assert!(!Owner { boot: "other".into(), pid: 4_000_000, ..me.clone() }.gone(&me));
        assert!(!Owner { start: 0, pid: 4_000_000, ..me.clone() }.gone(&me), "unknown start time");
        assert!(Owner { pid: 4_000_000, ..me.clone() }.gone(&me));
    }

    #[test]
    fn tokens_name_their_owner() {
        let me = Owner::me();
        let t = me.token();
        let back = Owner::from_token(&t).unwrap();
        assert_eq!((back.pid, back.start, back.pidns), (me.pid, me.start, me.pidns));
        assert!(!Owner::token_gone(&t, &me));
        assert!(Owner::token_gone(&Owner { pid: 4_000_000, ..me.clone() }.token(), &me));
        assert!(!Owner::token_gone("12345", &me));
        assert!(!Owner::token_gone(&Owner { boot: "0123abcd".into(), pid: 4_000_000, ..me.clone() }.token(), &me));
        assert_ne!(random_u64(), random_u64());
    }
}
