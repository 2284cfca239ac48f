//! Resource use of this process and of the children it waits for: CPU
//! time and peak memory, through `getrusage` and `wait4`.

use anyhow::{bail, Result};

/// The resource use of this process (`libc::RUSAGE_SELF`) or of all the
/// children it has waited for (`libc::RUSAGE_CHILDREN`).
pub fn of(who: libc::c_int) -> libc::rusage {
    // SAFETY: getrusage only writes the struct it is given.
    unsafe {
        let mut usage = std::mem::zeroed::<libc::rusage>();
        libc::getrusage(who, &mut usage);
        usage
    }
}

/// User + system CPU seconds of `usage`.
pub fn cpu_seconds(usage: &libc::rusage) -> f64 {
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    seconds(usage.ru_utime) + seconds(usage.ru_stime)
}

/// Waits for the child `pid`: its exit status (0 for success) and its own
/// resource use, peak memory included.
pub fn wait(pid: u32) -> Result<(i32, libc::rusage)> {
    let mut status = 0;
    // SAFETY: wait4 only writes the status and the struct it is given.
    let usage = unsafe {
        let mut usage = std::mem::zeroed::<libc::rusage>();
        if libc::wait4(pid as libc::pid_t, &mut status, 0, &mut usage) < 0 {
            bail!("wait4: {}", std::io::Error::last_os_error());
        }
        usage
    };
    let code = if libc::WIFEXITED(status) {
        libc::WEXITSTATUS(status)
    } else {
        -1
    };
    Ok((code, usage))
}

/// Fixes glibc's threshold above which an allocation is a mapping of its
/// own at its default, 128 KiB. glibc raises it as large blocks are freed,
/// so after the other scenes' renders the 1.1M-triangle build took 0.41 s
/// in this process against 0.32 s as the first work of a process, as in a
/// `tracer render` (its time there: 0.31-0.34 s either way).
/// (glibc's alone: elsewhere this does nothing.)
pub fn fix_mmap_threshold() {
    // SAFETY: mallopt only sets an allocator parameter.
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 128 * 1024);
    }
}
