//! `cargo xtask farm-test --slurm`: a real single-node Slurm on this
//! machine, for the test of `farm/slurm/*.sbatch`. Debian's packages are
//! installed if missing; munged, slurmctld and slurmd then run as children
//! of this process, with a private key, configuration, state, sockets and
//! ports in a temporary folder, so that nothing of the system's own
//! (`/etc/slurm`, `/etc/munge`, a running Slurm or munged) is read or
//! changed; they are stopped when the [`Cluster`] is dropped, on failure too.

use anyhow::{bail, ensure, Context, Result};
use std::fs;
use std::io::Read;
use std::net::TcpListener;
use std::os::unix::fs::PermissionsExt;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::sleep;
use std::time::{Duration, Instant};

/// The Debian packages of Slurm's source package `slurm-wlm` that a
/// single node needs; the `slurm-wlm` metapackage would add some thirty
/// plugin packages (HDF5, InfluxDB, IPMI, ...) that nothing here loads.
pub const PACKAGES: [&str; 4] = ["slurmctld", "slurmd", "slurm-client", "munge"];
const COMMANDS: [&str; 7] = [
    "munged",
    "slurmctld",
    "slurmd",
    "sbatch",
    "sinfo",
    "scancel",
    "scontrol",
];

/// This machine as slurmd sees it (`slurmd -C`).
#[derive(Debug, PartialEq)]
pub struct Node {
    pub name: String,
    pub cpus: u32,
    pub memory_mb: u64,
}

/// Reads `slurmd -C`'s first line, `NodeName=vm CPUs=2 ... RealMemory=24105`.
pub fn parse_node(slurmd_c: &str) -> Result<Node> {
    let line = slurmd_c.lines().next().unwrap_or_default();
    let field = |key: &str| {
        line.split_whitespace()
            .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
            .with_context(|| format!("`slurmd -C` gave no {key}= in {line:?}"))
    };
    Ok(Node {
        name: field("NodeName")?.to_string(),
        cpus: field("CPUs")?.parse().context("slurmd -C: CPUs")?,
        memory_mb: field("RealMemory")?
            .parse()
            .context("slurmd -C: RealMemory")?,
    })
}

/// Where the daemons keep their files, and their ports.
pub struct Layout {
    pub dir: PathBuf,
    pub munge_socket: PathBuf,
    pub ctld_port: u16,
    pub slurmd_port: u16,
}

/// A one-node `slurm.conf`. Nothing needs cgroups or systemd, which a
/// container may lack: processes are tracked through /proc
/// (proctrack/linuxproc), tasks are not bound (task/none), nothing is
/// accounted. Everyone runs as root, the only user that can start slurmd.
pub fn slurm_conf(node: &Node, layout: &Layout) -> String {
    let dir = layout.dir.display();
    format!(
        "# cargo xtask farm-test --slurm: one node, everything under {dir}
ClusterName=tracer-farm-test
SlurmctldHost={name}(127.0.0.1)
SlurmctldPort={ctld_port}
SlurmdPort={slurmd_port}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={socket}
StateSaveLocation={dir}/state
SlurmdSpoolDir={dir}/spool
SlurmctldPidFile={dir}/slurmctld.pid
SlurmdPidFile={dir}/slurmd.pid
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
MailProg=/bin/true
# Refuse at once what this node can never run, rather than let it pend
# (and `sbatch --wait` with it) forever; likewise a merge whose tiles failed.
EnforcePartLimits=ALL
SchedulerParameters=kill_invalid_depend
# `sbatch --wait` polls after 2 s, then 8 s later, then every 32 s, unless
# MinJobAge / 2 <= 8: then every 8 s. A finished job stays listed (for it
# and for `scontrol show job`) for MinJobAge = 17 s, two polls' worth.
MinJobAge=17
ReturnToService=2
NodeName={name} NodeAddr=127.0.0.1 CPUs={cpus} RealMemory={memory} State=UNKNOWN
PartitionName=farm Nodes={name} Default=YES MaxTime=INFINITE State=UP
",
        name = node.name,
        ctld_port = layout.ctld_port,
        slurmd_port = layout.slurmd_port,
        socket = layout.munge_socket.display(),
        cpus = node.cpus,
        memory = node.memory_mb,
    )
}

/// Installs [`PACKAGES`] unless every command is there already; returns
/// what it did, for the report.
pub fn install() -> Result<String> {
    ensure_root()?;
    let missing: Vec<&str> = COMMANDS.into_iter().filter(|c| !on_path(c)).collect();
    if missing.is_empty() {
        return Ok("packages already installed".into());
    }
    ensure!(
        on_path("apt-get"),
        "--slurm needs {} but finds no {} and no apt-get to install {}: install Slurm and \
         munge by hand",
        COMMANDS.join(", "),
        missing.join(", "),
        PACKAGES.join(" ")
    );
    let _no_start = NoServiceStart::new()?;
    apt(&["update", "-q"])?;
    let mut install = vec!["install", "-y", "-q", "--no-install-recommends"];
    install.extend(PACKAGES);
    apt(&install)?;
    let still: Vec<&str> = COMMANDS.into_iter().filter(|c| !on_path(c)).collect();
    ensure!(still.is_empty(), "installed, yet no {}", still.join(", "));
    Ok(format!("apt-get installed {}", PACKAGES.join(" ")))
}

/// Fails unless this process runs as root.
pub fn ensure_root() -> Result<()> {
    ensure!(
        // SAFETY: geteuid has no preconditions and cannot fail.
        unsafe { libc::geteuid() } == 0,
        "--slurm must run as root: it installs Slurm and munge and starts slurmd, which runs \
         jobs as their users (sudo -E cargo xtask farm-test --slurm)"
    );
    Ok(())
}

fn apt(args: &[&str]) -> Result<()> {
    let out = Command::new("apt-get")
        .args(args)
        .env("DEBIAN_FRONTEND", "noninteractive")
        .output()
        .context("cannot run apt-get")?;
    ensure!(
        out.status.success(),
        "apt-get {} failed ({}):\n{}",
        args.join(" "),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    Ok(())
}

/// Keeps the packages' scripts from starting the system's munge and Slurm
/// services while installing (Debian's policy-rc.d, exit 101 = "not now");
/// an existing policy is left as it is, and ours is removed afterwards.
struct NoServiceStart(Option<PathBuf>);

impl NoServiceStart {
    fn new() -> Result<Self> {
        let path = PathBuf::from("/usr/sbin/policy-rc.d");
        if path.exists() {
            return Ok(Self(None));
        }
        fs::write(
            &path,
            "#!/bin/sh\n# cargo xtask farm-test --slurm, removed after apt-get\nexit 101\n",
        )
        .with_context(|| format!("cannot write {}", path.display()))?;
        fs::set_permissions(&path, fs::Permissions::from_mode(0o755))?;
        Ok(Self(Some(path)))
    }
}

impl Drop for NoServiceStart {
    fn drop(&mut self) {
        if let Some(path) = &self.0 {
            let _ = fs::remove_file(path);
        }
    }
}

fn on_path(command: &str) -> bool {
    let path = std::env::var_os("PATH").unwrap_or_default();
    // Root's daemons live in sbin, which a user's PATH may lack.
    std::env::split_paths(&path)
        .chain(["/usr/sbin".into(), "/sbin".into()])
        .any(|dir| dir.join(command).is_file())
}

/// A running single-node Slurm; dropping it cancels what is left of the
/// jobs and stops the daemons, last started first.
pub struct Cluster {
    daemons: Vec<Daemon>,
    conf: PathBuf,
    pub node: Node,
    // Dropped after the daemons (fields drop in order): they write in it.
    dir: tempfile::TempDir,
}

struct Daemon {
    name: &'static str,
    child: Child,
    log: PathBuf,
}

impl Cluster {
    /// Starts munged, slurmctld and slurmd, and waits until the node is idle.
    pub fn start() -> Result<Cluster> {
        catch_interrupts();
        let dir = tempfile::Builder::new()
            .prefix("tracer-slurm-")
            .tempdir()
            .context("cannot make a folder for Slurm")?;
        // munged wants every folder above its socket open to all.
        fs::set_permissions(dir.path(), fs::Permissions::from_mode(0o755))?;
        for sub in ["log", "state", "spool", "run", "jobs"] {
            fs::create_dir(dir.path().join(sub))?;
        }
        let node = parse_node(&output(Command::new(sbin("slurmd")).arg("-C"))?)?;
        let mut cluster = Cluster {
            daemons: Vec::new(),
            conf: dir.path().join("slurm.conf"),
            node,
            dir,
        };
        cluster.start_munge()?;
        let (ctld_port, slurmd_port) = free_ports()?;
        let layout = Layout {
            dir: cluster.dir.path().to_path_buf(),
            munge_socket: cluster.munge_socket(),
            ctld_port,
            slurmd_port,
        };
        fs::write(&cluster.conf, slurm_conf(&cluster.node, &layout))?;
        let conf = cluster.conf.clone();
        cluster.spawn(
            "slurmctld",
            Command::new(sbin("slurmctld"))
                .arg("-D")
                .arg("-f")
                .arg(&conf),
        )?;
        cluster.spawn(
            "slurmd",
            Command::new(sbin("slurmd")).arg("-D").arg("-f").arg(&conf),
        )?;
        cluster.wait_idle(Duration::from_secs(60))?;
        Ok(cluster)
    }

    fn munge_socket(&self) -> PathBuf {
        self.dir.path().join("run/munge.socket")
    }

    /// munged with a key of its own (the system's, if any, is not read).
    fn start_munge(&mut self) -> Result<()> {
        let keys = self.dir.path().join("munge");
        fs::create_dir(&keys)?;
        fs::set_permissions(&keys, fs::Permissions::from_mode(0o700))?;
        let key = keys.join("munge.key");
        let mut bytes = vec![0u8; 1024];
        fs::File::open("/dev/urandom")?.read_exact(&mut bytes)?;
        fs::write(&key, &bytes)?;
        fs::set_permissions(&key, fs::Permissions::from_mode(0o600))?;
        let run = self.dir.path().join("run");
        let socket = self.munge_socket();
        let mut munged = Command::new(sbin("munged"));
        munged
            .arg("--foreground")
            .arg(format!("--socket={}", socket.display()))
            .arg(format!("--key-file={}", key.display()))
            .arg(format!("--pid-file={}", run.join("munged.pid").display()))
            .arg(format!("--seed-file={}", keys.join("seed").display()));
        self.spawn("munged", &mut munged)?;
        self.wait_for("munged's socket", Duration::from_secs(10), |_| {
            Ok(socket.exists())
        })
    }

    /// Starts a daemon in the foreground, as a child of this process, its
    /// output in log/NAME.log. It gets a process group of its own, so that
    /// a Ctrl-C reaches only this process, which then stops the daemons in
    /// order (jobs first).
    fn spawn(&mut self, name: &'static str, command: &mut Command) -> Result<()> {
        let log = self.dir.path().join(format!("log/{name}.log"));
        let file = fs::File::create(&log)?;
        let child = command
            .process_group(0)
            .stdin(Stdio::null())
            .stdout(file.try_clone()?)
            .stderr(file)
            .spawn()
            .with_context(|| format!("cannot start {name}"))?;
        self.daemons.push(Daemon { name, child, log });
        Ok(())
    }

    fn wait_idle(&mut self, limit: Duration) -> Result<()> {
        let node = self.node.name.clone();
        self.wait_for(&format!("node {node} idle in sinfo"), limit, |cluster| {
            let state = cluster.output(Command::new("sinfo").args(["-h", "-N", "-o", "%T"]));
            Ok(state.is_ok_and(|s| s.trim() == "idle"))
        })
    }

    /// Polls `ready` until it holds, failing (with the daemons' logs) when
    /// a daemon has died or `limit` has passed.
    fn wait_for(
        &mut self,
        what: &str,
        limit: Duration,
        mut ready: impl FnMut(&Self) -> Result<bool>,
    ) -> Result<()> {
        let start = Instant::now();
        loop {
            check_interrupted()?;
            if ready(self)? {
                return Ok(());
            }
            if let Some((name, status)) = self.exited()? {
                bail!(
                    "{name} exited ({status}) while waiting for {what}\n{}",
                    self.logs()
                );
            }
            if start.elapsed() > limit {
                bail!("no {what} after {limit:?}\n{}", self.logs());
            }
            sleep(Duration::from_millis(200));
        }
    }

    /// The first daemon found to have exited, and how.
    fn exited(&mut self) -> Result<Option<(&'static str, std::process::ExitStatus)>> {
        for daemon in &mut self.daemons {
            if let Some(status) = daemon.child.try_wait()? {
                return Ok(Some((daemon.name, status)));
            }
        }
        Ok(None)
    }

    /// The last lines of every daemon's log, for an error message.
    pub fn logs(&self) -> String {
        self.daemons
            .iter()
            .map(|d| {
                format!(
                    "--- {} ({}):\n{}",
                    d.name,
                    d.log.display(),
                    tail(&d.log, 15)
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// A Slurm command, run against this cluster's configuration.
    pub fn command(&self, program: &str) -> Command {
        let mut command = Command::new(program);
        command.env("SLURM_CONF", &self.conf);
        command
    }

    fn output(&self, command: &mut Command) -> Result<String> {
        output(command.env("SLURM_CONF", &self.conf))
    }

    /// A folder for the jobs' logs.
    pub fn jobs_dir(&self) -> PathBuf {
        self.dir.path().join("jobs")
    }

    /// Runs `sbatch --parsable --wait ARGS` and returns the job's id and
    /// times; a failed job is an error quoting the logs its tasks wrote.
    pub fn sbatch_wait(&self, args: &[String]) -> Result<Job> {
        let sbatch = self
            .command("sbatch")
            .args(["--parsable", "--wait"])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .context("cannot run sbatch")?;
        let out = wait_interruptibly(sbatch)?;
        // A Ctrl-C reaches sbatch too, which may end first.
        check_interrupted()?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        let id = stdout
            .trim()
            .split(';')
            .next()
            .unwrap_or_default()
            .to_string();
        if !out.status.success() {
            bail!(
                "sbatch {} failed ({}): {}\n{}",
                args.join(" "),
                out.status,
                String::from_utf8_lossy(&out.stderr).trim(),
                self.job_logs(&id)
            );
        }
        ensure!(!id.is_empty(), "sbatch printed no job id");
        // A job cancelled before it ran leaves `sbatch --wait` with exit 0.
        let job = self.output(Command::new("scontrol").args(["show", "job", &id]))?;
        let states = job_states(&job);
        ensure!(
            !states.is_empty() && states.iter().all(|s| s == "COMPLETED"),
            "job {id} ended {}, not COMPLETED:\n{job}\n{}",
            states.join(", "),
            self.job_logs(&id)
        );
        let span = job_span(&job).context("scontrol show job: no times")?;
        Ok(Job { id, span })
    }

    /// The logs of job ID's tasks (named `*-ID*.log` in [`Self::jobs_dir`]).
    fn job_logs(&self, id: &str) -> String {
        let Ok(entries) = fs::read_dir(self.jobs_dir()) else {
            return String::new();
        };
        let mut logs: Vec<PathBuf> = entries
            .filter_map(|e| Some(e.ok()?.path()))
            .filter(|p| !id.is_empty() && p.to_string_lossy().contains(&format!("-{id}")))
            .collect();
        logs.sort();
        logs.iter()
            .map(|p| format!("--- {}:\n{}", p.display(), tail(p, 10)))
            .collect::<Vec<_>>()
            .join("\n")
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        // A job left running (a failed or interrupted test) would outlive
        // slurmd: cancel it, and let slurmd end its processes first.
        let _ = self.command("scancel").arg("--me").output();
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(15) {
            let queue = self.output(Command::new("squeue").args(["-h", "--me"]));
            if queue.map_or(true, |q| q.trim().is_empty()) {
                break;
            }
            sleep(Duration::from_millis(200));
        }
        while let Some(mut daemon) = self.daemons.pop() {
            stop(&mut daemon.child);
        }
    }
}

/// A finished job.
pub struct Job {
    pub id: String,
    pub span: Span,
}

/// Where a job's time went, by slurmctld's clock (whole seconds).
#[derive(Debug, PartialEq)]
pub struct Span {
    /// From the submission to the first task's start.
    pub queued: i64,
    /// From the first task's start to the last one's end.
    pub ran: i64,
}

/// The span of a job's tasks from `scontrol show job`'s `SubmitTime`,
/// `StartTime` and `EndTime`.
pub fn job_span(show_job: &str) -> Option<Span> {
    let times = |key: &str| -> Option<Vec<i64>> {
        show_job
            .split_whitespace()
            .filter_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
            .map(epoch_seconds)
            .collect()
    };
    let submit = *times("SubmitTime")?.iter().min()?;
    let start = *times("StartTime")?.iter().min()?;
    let end = *times("EndTime")?.iter().max()?;
    Some(Span {
        queued: start - submit,
        ran: end - start,
    })
}

/// `2026-11-23T22:20:01` as seconds since 1970 (the offset cancels out of
/// the differences taken).
fn epoch_seconds(time: &str) -> Option<i64> {
    let (date, clock) = time.split_once('T')?;
    let num = |s: Option<&str>| s?.parse::<i64>().ok();
    let mut d = date.split('-');
    let (y, m, day) = (num(d.next())?, num(d.next())?, num(d.next())?);
    let mut c = clock.split(':');
    let (h, min, sec) = (num(c.next())?, num(c.next())?, num(c.next())?);
    // Days from the civil date (H. Hinnant's days_from_civil).
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let doy = (153 * ((m + 9) % 12) + 2) / 5 + day - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    let days = era * 146_097 + doe - 719_468;
    Some(days * 86_400 + h * 3600 + min * 60 + sec)
}

/// The `JobState` of every task in `scontrol show job` (one record per
/// array task).
pub fn job_states(show_job: &str) -> Vec<String> {
    show_job
        .split_whitespace()
        .filter_map(|kv| kv.strip_prefix("JobState="))
        .map(str::to_string)
        .collect()
}

/// Set by SIGINT or SIGTERM while the cluster runs.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

extern "C" fn on_interrupt(_: libc::c_int) {
    INTERRUPTED.store(true, Ordering::SeqCst);
}

/// From now on a Ctrl-C or a `kill` ends the test through [`Cluster`]'s
/// drop (which stops the daemons), not on the spot. Children get the
/// default action back when they exec, so an `sbatch --wait` ends at once.
fn catch_interrupts() {
    let handler = on_interrupt as extern "C" fn(libc::c_int);
    for signal in [libc::SIGINT, libc::SIGTERM] {
        // SAFETY: the handler only stores to an atomic, which is
        // async-signal-safe.
        unsafe { libc::signal(signal, handler as libc::sighandler_t) };
    }
}

fn check_interrupted() -> Result<()> {
    ensure!(
        !INTERRUPTED.load(Ordering::SeqCst),
        "interrupted: stopping the Slurm daemons"
    );
    Ok(())
}

/// Waits for a child, killing it if this process is interrupted.
fn wait_interruptibly(mut child: Child) -> Result<std::process::Output> {
    while child.try_wait()?.is_none() {
        if INTERRUPTED.load(Ordering::SeqCst) {
            let _ = child.kill();
            let _ = child.wait();
            check_interrupted()?;
        }
        sleep(Duration::from_millis(100));
    }
    Ok(child.wait_with_output()?)
}

/// SIGTERM, then SIGKILL if the daemon is still there after 15 s.
fn stop(child: &mut Child) {
    if let Ok(pid) = libc::pid_t::try_from(child.id()) {
        // SAFETY: the pid is our own child's, not yet reaped (so not reused).
        unsafe { libc::kill(pid, libc::SIGTERM) };
    }
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(15) {
        if !matches!(child.try_wait(), Ok(None)) {
            return;
        }
        sleep(Duration::from_millis(100));
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// A daemon's path: root's PATH has sbin, `sudo` may not keep it.
fn sbin(name: &str) -> PathBuf {
    ["/usr/sbin", "/sbin"]
        .iter()
        .map(|dir| Path::new(dir).join(name))
        .find(|p| p.is_file())
        .unwrap_or_else(|| name.into())
}

/// Two TCP ports nothing listens on now (a Slurm of the system's own may
/// hold the usual 6817 and 6818); both are held at once, so they differ.
fn free_ports() -> Result<(u16, u16)> {
    let a = TcpListener::bind("127.0.0.1:0")?;
    let b = TcpListener::bind("127.0.0.1:0")?;
    Ok((a.local_addr()?.port(), b.local_addr()?.port()))
}

fn output(command: &mut Command) -> Result<String> {
    let out = command
        .output()
        .with_context(|| format!("cannot run {command:?}"))?;
    ensure!(
        out.status.success(),
        "{command:?} failed ({}): {}",
        out.status,
        String::from_utf8_lossy(&out.stderr).trim()
    );
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

fn tail(path: &Path, lines: usize) -> String {
    let text = fs::read_to_string(path).unwrap_or_default();
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_node_from_slurmd_c() {
        let text = "NodeName=node7 CPUs=12 Boards=1 SocketsPerBoard=1 CoresPerSocket=6 \
                    ThreadsPerCore=2 RealMemory=64000\nUpTime=0-03:07:42\n";
        let node = parse_node(text).unwrap();
        assert_eq!(
            node,
            Node {
                name: "node7".into(),
                cpus: 12,
                memory_mb: 64000
            }
        );
        assert!(parse_node("UpTime=1\n").is_err());
        assert!(parse_node("NodeName=a CPUs=two RealMemory=1").is_err());
    }

    #[test]
    fn reads_every_array_task_s_state() {
        let show = "JobId=3 ArrayJobId=2 ArrayTaskId=1 JobName=tracer-tiles\n   \
                    JobState=COMPLETED Reason=None Dependency=(null)\n\n\
                    JobId=2 ArrayJobId=2 ArrayTaskId=0 JobName=tracer-tiles\n   \
                    JobState=FAILED Reason=NonZeroExitCode Dependency=(null)\n";
        assert_eq!(job_states(show), ["COMPLETED", "FAILED"]);
    }

    #[test]
    fn a_job_s_span_runs_from_the_first_start_to_the_last_end() {
        // Two tasks over midnight on new year's eve of a leap year.
        let show = "SubmitTime=2024-12-31T23:59:58 EligibleTime=2024-12-31T23:59:58\n\
                    StartTime=2024-12-31T23:59:59 EndTime=2025-01-01T00:00:03\n\n\
                    SubmitTime=2024-12-31T23:59:58\n\
                    StartTime=2025-01-01T00:00:01 EndTime=2025-01-01T00:01:01\n";
        assert_eq!(job_span(show), Some(Span { queued: 1, ran: 62 }));
        // 1970-01-01 is day 0, 2000-03-01 day 11017 (30 years, 7 of them leap, then 31 + 29 days).
        assert_eq!(epoch_seconds("1970-01-01T00:00:10"), Some(10));
        assert_eq!(epoch_seconds("2000-03-01T00:00:00"), Some(11_017 * 86_400));
        assert_eq!(job_span("JobState=PENDING StartTime=Unknown"), None);
    }

    #[test]
    fn the_configuration_names_the_node_its_cpus_and_the_private_paths() {
        let node = Node {
            name: "node7".into(),
            cpus: 12,
            memory_mb: 64000,
        };
        let layout = Layout {
            dir: "/tmp/t".into(),
            munge_socket: "/tmp/t/run/munge.socket".into(),
            ctld_port: 40001,
            slurmd_port: 40002,
        };
        let conf = slurm_conf(&node, &layout);
        let lines: Vec<&str> = conf.lines().collect();
        for line in [
            "SlurmctldHost=node7(127.0.0.1)",
            "SlurmctldPort=40001",
            "SlurmdPort=40002",
            "AuthInfo=socket=/tmp/t/run/munge.socket",
            "StateSaveLocation=/tmp/t/state",
            "SlurmdSpoolDir=/tmp/t/spool",
            "ProctrackType=proctrack/linuxproc",
            "MinJobAge=17",
            "TaskPlugin=task/none",
            "NodeName=node7 NodeAddr=127.0.0.1 CPUs=12 RealMemory=64000 State=UNKNOWN",
            "PartitionName=farm Nodes=node7 Default=YES MaxTime=INFINITE State=UP",
        ] {
            assert!(lines.contains(&line), "no {line:?} in\n{conf}");
        }
        // Nothing may ask for cgroups (a container may have none to give).
        assert!(!conf.contains("cgroup"), "{conf}");
    }
}
