//! Ctrl-C (SIGINT) and SIGTERM during a sweep: the sweep stops cleanly
//! instead of dying mid-write. A signal handler only writes the signal's
//! number to a pipe (all it may safely do); a thread reading the pipe runs
//! the sweep's `on_signal`, which waits for any row being written, removes
//! its own temporary files and the folder's lock, says what was saved and
//! how to go on, and exits with 128 + the signal's number (130, 143). With
//! no sweep under way the signal does what it would have done.

use std::sync::Mutex;

type OnSignal = Box<dyn Fn(i32) + Send>;

static ACTIVE: Mutex<Option<OnSignal>> = Mutex::new(None);

/// While alive, SIGINT and SIGTERM run `on_signal` (given the signal's
/// number) instead of killing the process at once.
pub struct Guard(());

impl Guard {
    pub fn new(on_signal: impl Fn(i32) + Send + 'static) -> Guard {
        imp::install();
        *ACTIVE.lock().unwrap_or_else(|e| e.into_inner()) = Some(Box::new(on_signal));
        Guard(())
    }
}

impl Drop for Guard {
    fn drop(&mut self) {
        *ACTIVE.lock().unwrap_or_else(|e| e.into_inner()) = None;
    }
}

/// The exit status a shell gives a process ended by `signal`.
pub fn status_of(signal: i32) -> i32 {
    128 + signal
}

/// A signal's name for messages.
pub fn name(signal: i32) -> &'static str {
    match signal {
        2 => "Ctrl-C (SIGINT)",
        15 => "SIGTERM",
        _ => "a signal",
    }
}

#[cfg(unix)]
mod imp {
    use std::sync::atomic::{AtomicI32, Ordering::Relaxed};
    use std::sync::Once;

    static PIPE: AtomicI32 = AtomicI32::new(-1);

    extern "C" fn on_signal(sig: libc::c_int) {
        let fd = PIPE.load(Relaxed);
        if fd >= 0 {
            let b = sig as u8;
            // SAFETY: write(2) is async-signal-safe; `b` lives for the call.
            unsafe { libc::write(fd, &b as *const u8 as *const libc::c_void, 1) };
        }
    }

    fn dispatch(sig: i32) {
        let active = super::ACTIVE.lock().unwrap_or_else(|e| e.into_inner());
        match active.as_ref() {
            Some(f) => f(sig),
            None => {
                drop(active);
                // SAFETY: restoring the default action and raising the
                // signal again ends the process as the signal would have.
                unsafe {
                    libc::signal(sig, libc::SIG_DFL);
                    libc::raise(sig);
                }
            }
        }
    }

    pub fn install() {
        static ONCE: Once = Once::new();
        ONCE.call_once(|| {
            let mut fds = [0 as libc::c_int; 2];
            // SAFETY: `fds` has room for the two descriptors pipe(2) writes.
            if unsafe { libc::pipe(fds.as_mut_ptr()) } != 0 {
                return;
            }
            PIPE.store(fds[1], Relaxed);
            let read = fds[0];
            let spawned = std::thread::Builder::new().name("signals".into()).spawn(move || loop {
                let mut b = 0u8;
                // SAFETY: reads one byte into `b`, which outlives the call.
                let n = unsafe { libc::read(read, &mut b as *mut u8 as *mut libc::c_void, 1) };
                if n == 1 {
                    dispatch(b as i32);
                } else if n < 0 && std::io::Error::last_os_error().kind() == std::io::ErrorKind::Interrupted {
                    continue;
                } else {
                    break;
                }
            });
            if spawned.is_err() {
                return;
            }
            for sig in [libc::SIGINT, libc::SIGTERM] {
                // SAFETY: a zeroed sigaction with a handler that only calls
                // write(2); SA_RESTART so other threads' calls go on.
                unsafe {
                    let mut sa: libc::sigaction = std::mem::zeroed();
                    sa.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
                    sa.sa_flags = libc::SA_RESTART;
                    libc::sigemptyset(&mut sa.sa_mask);
                    libc::sigaction(sig, &sa, std::ptr::null_mut());
                }
            }
        });
    }
}

#[cfg(not(unix))]
mod imp {
    pub fn install() {}
}
