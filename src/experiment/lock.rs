//! A folder's lock: `DIR/.lock`, which one sweep (or merge) at a time
//! holds while it writes the folder's record.
//!
//! The lock is made whole before it appears: its text (host, boot id, pid
//! namespace, pid, start time, a random token) goes into a temporary file,
//! which is then hard-linked to `.lock`, a step that fails if `.lock` is
//! already there; two sweeps started together cannot both succeed, and
//! no one ever reads a lock without its owner. A lock is taken over only
//! when its owner is provably gone on this host (`owner::Owner::gone`):
//! never when it was written on another host, in another container or pid
//! namespace, or cannot be read; those are refused with the holder named,
//! and `--break-lock` removes them. The lock is removed by its holder only
//! while it still holds that holder's token.

use crate::owner::{random_u64, Owner};
use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum LockError {
    #[error("{path}: held by {holder}; wait for it to finish, or if it is no longer running, run again with --break-lock")]
    Held { path: String, holder: String },
    #[error("{path}: cannot tell who holds it ({why}); if nothing is writing this folder, run again with --break-lock")]
    Unreadable { path: String, why: String },
    #[error("{path}: cannot create the folder's lock: {source}")]
    Io { path: String, source: std::io::Error },
}

/// What a lock file says of its holder.
#[derive(Clone, Debug, PartialEq)]
pub struct Holder {
    pub owner: Owner,
    /// Seconds since the Unix epoch when the lock was taken.
    pub since: u64,
    pub token: String,
    /// The command that holds the lock (for the message).
    pub command: String,
}

impl Holder {
    fn text(&self) -> String {
        let o = &self.owner;
        format!(
            "refract lock\nhost={}\nboot={}\npidns={}\npid={}\nstart={}\nsince={}\ntoken={}\ncommand={}\n",
            o.host,
            o.boot,
            o.pidns,
            o.pid,
            o.start,
            self.since,
            self.token,
            self.command.replace('\n', " ")
        )
    }

    fn parse(text: &str) -> Option<Holder> {
        let mut lines = text.lines();
        if lines.next()? != "refract lock" {
            return None;
        }
        let kv: std::collections::HashMap<&str, &str> = lines.filter_map(|l| l.split_once('=')).collect();
        let owner = Owner {
            host: kv.get("host")?.to_string(),
            boot: kv.get("boot")?.to_string(),
            pidns: kv.get("pidns")?.parse().ok()?,
            pid: kv.get("pid")?.parse().ok()?,
            start: kv.get("start")?.parse().ok()?,
        };
        let token = kv.get("token")?.to_string();
        if token.is_empty() {
            return None;
        }
        Some(Holder { owner, since: kv.get("since")?.parse().ok()?, token, command: kv.get("command").unwrap_or(&"").to_string() })
    }

    /// "pid 123 on host h (another pid namespace), since 2026-11-25 02:40 UTC: refract sweep ..."
    pub fn describe(&self, me: &Owner) -> String {
        let o = &self.owner;
        let place = if me.sees(o) {
            String::new()
        } else if o.boot == me.boot {
            " (in another container or pid namespace, which this process cannot see into)".into()
        } else {
            " (another host, or before a reboot: this process cannot see it)".into()
        };
        let cmd = if self.command.is_empty() { String::new() } else { format!(": {}", self.command) };
        format!("pid {} on host {}{place}, since {}{cmd}", o.pid, if o.host.is_empty() { "?" } else { &o.host }, utc(self.since))
    }
}

/// Seconds since the epoch as `YYYY-MM-DD HH:MM UTC` (civil-from-days,
/// H. Hinnant, "chrono-Compatible Low-Level Date Algorithms").
pub fn utc(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let (h, m) = (secs % 86_400 / 3600, secs % 3600 / 60);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let mo = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(mo <= 2);
    format!("{y:04}-{mo:02}-{d:02} {h:02}:{m:02} UTC")
}

/// A held lock; removed when dropped (if it still holds our token).
#[derive(Debug)]
pub struct FolderLock {
    path: PathBuf,
    token: String,
}

/// What `take` found and did, for the message.
#[derive(Debug)]
pub enum Taken {
    Fresh,
    /// A lock whose owner was provably gone, taken over.
    Stale(String),
    /// A lock removed by `--break-lock`.
    Broken(String),
}

impl FolderLock {
    /// Takes `dir`'s lock for `command`. With `break_lock`, a lock held by
    /// anyone else is removed first (its holder named in `Taken::Broken`).
    pub fn take(dir: &Path, command: &str, break_lock: bool) -> Result<(FolderLock, Taken), LockError> {
        let me = Owner::me();
        let path = dir.join(".lock");
        let shown = path.display().to_string();
        let io = |source: std::io::Error| LockError::Io { path: shown.clone(), source };
        let since = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
        let holder = Holder { owner: me.clone(), since, token: format!("{:016x}", random_u64()), command: command.to_string() };
        let tmp = dir.join(format!(".lock.{}.tmp", me.token()));
        crate::image_io::write_text(&tmp, &holder.text()).map_err(|e| io(std::io::Error::other(format!("{e:#}"))))?;
        let result = Self::place(&path, &tmp, &me, break_lock);
        let _ = std::fs::remove_file(&tmp);
        let taken = result?;
        Ok((FolderLock { path, token: holder.token }, taken))
    }

    fn place(path: &Path, tmp: &Path, me: &Owner, break_lock: bool) -> Result<Taken, LockError> {
        let shown = path.display().to_string();
        let io = |source: std::io::Error| LockError::Io { path: shown.clone(), source };
        let mut taken = Taken::Fresh;
        for _ in 0..4 {
            match std::fs::hard_link(tmp, path) {
                Ok(()) => return Ok(taken),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(e) => return Err(io(e)),
            }
            let text = match std::fs::read_to_string(path) {
                Ok(t) => t,
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
                Err(e) => return Err(io(e)),
            };
            let found = Holder::parse(&text);
            let named = found.as_ref().map_or_else(|| format!("an unreadable lock ({} bytes)", text.len()), |h| h.describe(me));
            if !break_lock {
                match &found {
                    None => {
                        let why = if text.trim().is_empty() { "it is empty".to_string() } else { "it is not a lock this version of refract wrote".to_string() };
                        return Err(LockError::Unreadable { path: shown, why });
                    }
                    Some(h) if !h.owner.gone(me) => return Err(LockError::Held { path: shown, holder: h.describe(me) }),
                    Some(_) => {}
                }
            }
            // Move the lock we judged aside, and check it is still the one
            // judged: another process may have taken over the same stale
            // lock in between, and its new lock must be put back.
            let aside = path.with_file_name(format!(".lock.{}.old.tmp", me.token()));
            match std::fs::rename(path, &aside) {
                Ok(()) => {}
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
                Err(e) => return Err(io(e)),
            }
            let moved = std::fs::read_to_string(&aside).unwrap_or_default();
            if moved != text {
                let _ = std::fs::hard_link(&aside, path);
                let _ = std::fs::remove_file(&aside);
                continue;
            }
            let _ = std::fs::remove_file(&aside);
            taken = if break_lock { Taken::Broken(named) } else { Taken::Stale(named) };
        }
        Err(LockError::Unreadable { path: shown, why: "it kept changing while being taken".into() })
    }

    /// Who holds `dir`'s lock, if anyone: `None` when there is no lock or
    /// its owner is provably gone, else the holder described.
    pub fn holder(dir: &Path) -> Option<String> {
        let text = std::fs::read_to_string(dir.join(".lock")).ok()?;
        let me = Owner::me();
        match Holder::parse(&text) {
            Some(h) if h.owner.gone(&me) => None,
            Some(h) => Some(h.describe(&me)),
            None => Some(format!("an unreadable lock ({} bytes)", text.len())),
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Removes the lock if it still holds our token (`--break-lock` by
    /// another process may have replaced it). Also what `Drop` does.
    pub fn release(&self) {
        let ours = std::fs::read_to_string(&self.path).ok().and_then(|t| Holder::parse(&t)).is_some_and(|h| h.token == self.token);
        if ours {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        self.release();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lock_is_whole_exclusive_and_released() {
        let dir = tempfile::tempdir().unwrap();
        let (lock, taken) = FolderLock::take(dir.path(), "refract sweep a.toml", false).unwrap();
        assert!(matches!(taken, Taken::Fresh));
        let text = std::fs::read_to_string(dir.path().join(".lock")).unwrap();
        let h = Holder::parse(&text).unwrap();
        assert_eq!((h.owner.pid, h.command.as_str()), (std::process::id(), "refract sweep a.toml"));
        // Held by this live process: a second taker is refused, by name.
        let err = FolderLock::take(dir.path(), "b", false).unwrap_err().to_string();
        assert!(err.contains(&format!("held by pid {} on host", std::process::id())) && err.contains("--break-lock"), "{err}");
        assert_eq!(FolderLock::holder(dir.path()).map(|h| h.contains("refract sweep a.toml")), Some(true));
        drop(lock);
        assert!(!dir.path().join(".lock").exists());
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn only_a_provably_gone_owner_is_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let me = Owner::me();
        let write =
            |o: Owner| std::fs::write(dir.path().join(".lock"), Holder { owner: o, since: 0, token: "t".into(), command: String::new() }.text()).unwrap();
        write(Owner { pid: 4_000_000, ..me.clone() });
        let (lock, taken) = FolderLock::take(dir.path(), "c", false).unwrap();
        assert!(matches!(taken, Taken::Stale(_)));
        drop(lock);
        // Another pid namespace: its pid 4000000 may be alive there.
        write(Owner { pid: 4_000_000, pidns: me.pidns + 1, ..me.clone() });
        let err = FolderLock::take(dir.path(), "c", false).unwrap_err().to_string();
        assert!(err.contains("another container or pid namespace"), "{err}");
        // An empty lock is not taken for stale.
        std::fs::write(dir.path().join(".lock"), "").unwrap();
        let err = FolderLock::take(dir.path(), "c", false).unwrap_err().to_string();
        assert!(err.contains("cannot tell who holds it (it is empty)"), "{err}");
        let (lock, taken) = FolderLock::take(dir.path(), "c", true).unwrap();
        assert!(matches!(taken, Taken::Broken(_)));
        // Someone broke our lock and holds it now: we do not remove theirs.
        write(Owner { pid: 4_000_000, ..me.clone() });
        drop(lock);
        assert!(dir.path().join(".lock").exists());
    }

    #[test]
    fn utc_dates() {
        assert_eq!(utc(0), "1970-01-01 00:00 UTC");
        assert_eq!(utc(1_795_574_400), "2026-11-25 02:40 UTC");
    }
}
