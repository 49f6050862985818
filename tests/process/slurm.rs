//! The Slurm scripts of `scripts/slurm/` on a real Slurm: the commands of
//! docs/hpc.md ("On Slurm, and on one node"), run as they are written there,
//! against the single-node cluster of `scripts/slurm/local-cluster`.
//!
//! Runs when `TMC_SLURM` is set (`.ci/run` starts the cluster and sets it);
//! then a Slurm that cannot be reached fails the test, it does not skip.
//! Without `TMC_SLURM` the test says how to run it and passes.
//!
//! What it checks, one test each (they share the one node, so they take
//! turns):
//! * the commands exactly as documented (16 parts of a real CT and the
//!   dependent merge) give the bytes of a single `tmc extract`, and each part
//!   ran with the threads and memory Slurm gave it;
//! * a part whose input is damaged fails, keeps the merge from running, and
//!   `sacct` names the part (FAILED, exit code 1) while its log names the error;
//! * `scancel` of the array while a part is writing leaves no part file, no
//!   temporary file and no process behind (the part handles Slurm's SIGTERM);
//! * a part requeued while it runs (`scontrol requeue`, as when its node is
//!   lost) runs again and the merge still gives the bytes of a single run.

use crate::common;

use common::cli::{names, s, synth, temp_files, tmc, tmc_path};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Mutex, MutexGuard, OnceLock};
use std::time::{Duration, Instant};

/// The tests take turns on the cluster's one node.
static NODE: Mutex<()> = Mutex::new(());

/// The cluster, or `None` (after saying so) when `TMC_SLURM` is not set.
/// Panics when it is set and Slurm does not answer or its node is not up.
fn cluster() -> Option<MutexGuard<'static, ()>> {
    if std::env::var_os("TMC_SLURM").is_none_or(|v| v.is_empty()) {
        eprintln!(
            "skipped: set TMC_SLURM=1 with a Slurm to submit to, for example \
             eval \"$(scripts/slurm/local-cluster start)\"; TMC_SLURM=1 cargo test \
             --release --test process slurm::; scripts/slurm/local-cluster stop"
        );
        return None;
    }
    let guard = NODE.lock().unwrap_or_else(|e| e.into_inner());
    // Asked once: the tests after a failed first look fail at once.
    static REACHED: OnceLock<Result<(), String>> = OnceLock::new();
    if let Err(why) = REACHED.get_or_init(reach) {
        panic!("TMC_SLURM is set but {why}; see scripts/slurm/local-cluster and its logs");
    }
    Some(guard)
}

/// Whether Slurm answers with a node up, and if not, what went wrong.
fn reach() -> Result<(), String> {
    if let Some(conf) = std::env::var_os("SLURM_CONF") {
        if !Path::new(&conf).is_file() {
            return Err(format!("SLURM_CONF names no file ({conf:?})"));
        }
    }
    // sinfo retries for a minute when it has no configuration at all.
    let out = Command::new("timeout")
        .args(["30", "sinfo", "-h", "-N", "-o", "%t"])
        .output()
        .map_err(|e| format!("sinfo cannot run ({e})"))?;
    let states = String::from_utf8_lossy(&out.stdout).into_owned();
    let up = ["idle", "mix", "alloc"];
    match out.status.success() && states.lines().any(|t| up.contains(&t.trim())) {
        true => Ok(()),
        false => Err(format!(
            "Slurm has no node up (sinfo: {states:?} {})",
            String::from_utf8_lossy(&out.stderr).trim()
        )),
    }
}

/// The docs' commands (the `sh` block under "On Slurm" in docs/hpc.md).
fn documented_commands() -> String {
    let doc = fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/hpc.md"))
        .expect("read docs/hpc.md");
    let section = &doc[doc
        .find("### On Slurm")
        .expect("docs/hpc.md: On Slurm section")..];
    let start = section.find("```sh\n").expect("an sh block") + "```sh\n".len();
    let end = start + section[start..].find("```").expect("end of the sh block");
    let block = section[start..end].to_string();
    assert!(
        block.contains("sbatch --dependency=afterok:$jid") && block.contains("--array=1-$N"),
        "docs/hpc.md's Slurm commands changed: {block}"
    );
    block
}

/// `text` with `from` replaced by `to` (which must be there).
fn with(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "{from:?} not in {text:?}");
    text.replacen(from, to, 1)
}

/// A directory to submit from: `scripts` of this checkout linked in, so the
/// documented relative paths work.
fn submit_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let scripts = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts");
    std::os::unix::fs::symlink(scripts, dir.path().join("scripts")).unwrap();
    dir
}

/// The job ids of one submission: the array of parts and the merge.
struct Jobs {
    parts: String,
    merge: String,
}

/// A test that fails half-way leaves no job behind for the next one.
impl Drop for Jobs {
    fn drop(&mut self) {
        let _ = Command::new("scancel")
            .args([&self.parts, &self.merge])
            .stderr(std::process::Stdio::null())
            .status();
    }
}

/// Runs `commands` in `dir` with bash, the built `tmc` first on `PATH` (the
/// jobs inherit it: `--export=ALL`).
fn submit(dir: &Path, commands: &str) -> Jobs {
    let bin = Path::new(tmc_path()).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let script = format!("set -euo pipefail\n{commands}\necho \"parts job $jid\"\n");
    let out = Command::new("bash")
        .args(["-c", &script])
        .current_dir(dir)
        .env("PATH", path)
        .output()
        .expect("run bash");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "the documented commands failed: {stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let after = |prefix: &str| {
        let line = stdout.lines().find_map(|l| l.strip_prefix(prefix));
        let id = line.unwrap_or_else(|| panic!("no {prefix:?} in {stdout:?}"));
        // --parsable prints "id" or "id;cluster"
        id.split(';').next().unwrap().trim().to_string()
    };
    Jobs {
        parts: after("parts job "),
        merge: after("Submitted batch job "),
    }
}

/// Runs a Slurm command; panics with its output if it fails.
fn slurm(program: &str, args: &[&str]) -> String {
    let out = Command::new(program)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {program}: {e}"));
    assert!(
        out.status.success(),
        "{program} {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Waits until none of `jobs` is pending, running or completing.
fn wait_until_done(jobs: &Jobs, limit: Duration) {
    let ids = format!("{},{}", jobs.parts, jobs.merge);
    let start = Instant::now();
    loop {
        let queued = slurm("squeue", &["-h", "-j", &ids, "-o", "%i %t %r"]);
        if queued.trim().is_empty() {
            return;
        }
        assert!(
            start.elapsed() < limit,
            "jobs {ids} still queued after {limit:?}:\n{queued}"
        );
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// One line of `sacct`: a job (or array task) and how it ended.
#[derive(Debug, Clone)]
struct Record {
    id: String,
    state: String,
    exit: String,
    start: String,
    /// The nodes allocated (`None assigned` for a job that never ran).
    nodes: String,
}

/// sacct's records of the allocations of `job` (array tasks `job_I`), all
/// of them (requeued runs too), once it has one for every task in a final
/// state: slurmdbd receives them a moment after the jobs end.
fn accounting(job: &str, tasks: usize) -> Vec<Record> {
    let start = Instant::now();
    loop {
        let text = slurm(
            "sacct",
            &[
                "-n",
                "-P",
                "-X",
                "-D",
                "-j",
                job,
                "--format=JobID,State,ExitCode,Start,NodeList",
            ],
        );
        let records: Vec<Record> = text
            .lines()
            .map(|l| {
                let f: Vec<&str> = l.split('|').collect();
                Record {
                    id: f[0].to_string(),
                    state: f[1].split(' ').next().unwrap().to_string(),
                    exit: f[2].to_string(),
                    start: f[3].to_string(),
                    nodes: f[4].to_string(),
                }
            })
            .collect();
        let open = ["PENDING", "RUNNING", "REQUEUED", "COMPLETING"];
        let final_ids: std::collections::BTreeSet<&str> = records
            .iter()
            .filter(|r| !open.contains(&r.state.as_str()))
            .map(|r| r.id.as_str())
            .collect();
        let all_final = records
            .iter()
            .filter(|r| r.state != "REQUEUED")
            .all(|r| !open.contains(&r.state.as_str()));
        if final_ids.len() >= tasks && all_final {
            return records;
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "sacct has no final record of every task of job {job}:\n{text}"
        );
        std::thread::sleep(Duration::from_millis(300));
    }
}

/// The last record of `id` (a requeued task has one per run).
fn last<'a>(records: &'a [Record], id: &str) -> &'a Record {
    records
        .iter()
        .rev()
        .find(|r| r.id == id)
        .unwrap_or_else(|| panic!("no sacct record of {id}: {records:?}"))
}

/// The log of array task `task` of `job` (sbatch's default `slurm-%A_%a.out`).
fn task_log(dir: &Path, job: &str, task: usize) -> String {
    fs::read_to_string(dir.join(format!("slurm-{job}_{task}.out"))).unwrap_or_default()
}

/// `tmc extract INPUT --iso ISO -o OUTPUT`, the single run the merge must equal.
fn single_run(input: &Path, iso: &str, output: &Path) -> Vec<u8> {
    let out = tmc(&["extract", s(input), "--iso", iso, "-q", "-o", s(output)]);
    assert!(out.status.success(), "{out:?}");
    fs::read(output).unwrap()
}

/// Waits until array task `task` of `job` is running and its part's
/// temporary file exists in `parts` (the part is writing), and returns.
fn wait_until_writing(dir: &Path, jobs: &Jobs, task: usize) {
    let parts = dir.join("parts");
    let start = Instant::now();
    loop {
        let running = slurm("squeue", &["-h", "-t", "R", "-j", &jobs.parts, "-o", "%i"]);
        let writing = parts.is_dir() && !temp_files(&parts).is_empty();
        if writing
            && running
                .lines()
                .any(|l| l.trim() == format!("{}_{task}", jobs.parts))
        {
            return;
        }
        let done = slurm("squeue", &["-h", "-j", &jobs.parts, "-o", "%i"]);
        assert!(
            !done.trim().is_empty(),
            "the parts ended before part {task} was seen writing: make its volume larger \
             (log: {})",
            task_log(dir, &jobs.parts, task)
        );
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "part {task} not seen writing in 60 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Processes whose working directory is `dir` or below (what a job left).
fn processes_in(dir: &Path) -> Vec<String> {
    let dir = fs::canonicalize(dir).unwrap();
    let mut found = Vec::new();
    for entry in fs::read_dir("/proc").unwrap().flatten() {
        let cwd = entry.path().join("cwd");
        if let Ok(target) = fs::read_link(&cwd) {
            if target.starts_with(&dir) {
                let cmd = fs::read(entry.path().join("cmdline")).unwrap_or_default();
                found.push(String::from_utf8_lossy(&cmd).replace('\0', " "));
            }
        }
    }
    found
}

/// The smallest real CT of `../shared/data` (64x64x93 int16, also bundled
/// as `data/headsq_quarter.nrrd`, which stands in when that folder is absent).
fn ct() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shared = root.join("../shared/data/headsq_quarter.nrrd");
    if shared.is_file() {
        shared
    } else {
        eprintln!(
            "{} not found: using data/headsq_quarter.nrrd",
            shared.display()
        );
        root.join("data/headsq_quarter.nrrd")
    }
}

/// A head phantom whose parts take seconds (a dense surface: the brain's
/// noise at the isovalue), for catching a part while it writes.
const SLOW_ISO: &str = "1035";
fn slow_volume(dir: &Path) -> PathBuf {
    synth(dir, "head", "384,384,320", "u16", "head.nrrd")
}

/// Submits the documented commands for 2 parts of a [`slow_volume`] at
/// [`SLOW_ISO`], merged to `out`, and returns once part 1 is writing: the
/// submit directory, the volume and the jobs.
fn slow_parts_writing(out: &str) -> (tempfile::TempDir, PathBuf, Jobs) {
    let dir = submit_dir();
    let volume = slow_volume(dir.path());
    let commands = with(&documented_commands(), "N=16", "N=2");
    let commands = with(&commands, "IN=ct.nrrd", &format!("IN={}", s(&volume)));
    let commands = with(&commands, "ISO=550", &format!("ISO={SLOW_ISO}"));
    let commands = with(&commands, "OUT=ct.ply", &format!("OUT={out}"));
    let jobs = submit(dir.path(), &commands);
    wait_until_writing(dir.path(), &jobs, 1);
    (dir, volume, jobs)
}

#[test]
fn documented_commands_merge_to_the_bytes_of_one_run() {
    let Some(_node) = cluster() else { return };
    let dir = submit_dir();
    std::os::unix::fs::symlink(ct(), dir.path().join("ct.nrrd")).unwrap();
    // The commands exactly as written: N=16, IN=ct.nrrd, ISO=550, OUT=ct.ply.
    let jobs = submit(dir.path(), &documented_commands());
    wait_until_done(&jobs, Duration::from_secs(150));
    let parts = accounting(&jobs.parts, 16);
    for i in 1..=16 {
        let r = last(&parts, &format!("{}_{i}", jobs.parts));
        assert_eq!(
            (r.state.as_str(), r.exit.as_str()),
            ("COMPLETED", "0:0"),
            "part {i}: {}",
            task_log(dir.path(), &jobs.parts, i)
        );
    }
    let merge = accounting(&jobs.merge, 1);
    assert_eq!(last(&merge, &jobs.merge).state, "COMPLETED", "{merge:?}");
    let single = single_run(
        &dir.path().join("ct.nrrd"),
        "550",
        &dir.path().join("one.ply"),
    );
    let merged = fs::read(dir.path().join("ct.ply")).expect("the merge wrote ct.ply");
    assert!(
        merged == single,
        "the merged ct.ply differs from a single run"
    );
    assert_eq!(names(&dir.path().join("parts")).len(), 16);
    assert_eq!(temp_files(dir.path()), Vec::<String>::new());
    // Each part took the CPUs and memory of its allocation (--cpus-per-task=4,
    // --mem=4G: 4096 MiB less an eighth).
    let log = task_log(dir.path(), &jobs.parts, 3);
    assert!(
        log.contains("--threads 4 --max-memory 3584M") && log.contains("--part 3/16"),
        "part 3's command: {log}"
    );
}

/// Writes the planes of `volume` as a directory of Deflate-compressed int16
/// TIFF slices, the last one damaged (its compressed data overwritten, which
/// only shows when that plane is decoded). Returns the directory and the
/// damaged file's name.
fn damaged_tiff_stack(volume: &Path, dir: &Path) -> (PathBuf, String) {
    use tiff::encoder::{colortype::GrayI16, compression::DeflateLevel, Compression};
    let source = tmc::volume::open(volume, None).unwrap();
    let [nx, ny, nz] = source.grid().dims;
    let stack = dir.join("ct-slices");
    fs::create_dir(&stack).unwrap();
    let mut plane = vec![0.0; nx * ny];
    for z in 0..nz {
        source.read_plane(z, &mut plane).unwrap();
        let samples: Vec<i16> = plane.iter().map(|&v| v as i16).collect();
        let path = stack.join(format!("slice_{z:03}.tif"));
        let mut file = fs::File::create(&path).unwrap();
        tiff::encoder::TiffEncoder::new(&mut file)
            .unwrap()
            .with_compression(Compression::Deflate(DeflateLevel::Balanced))
            .write_image::<GrayI16>(nx as u32, ny as u32, &samples)
            .unwrap();
    }
    let name = format!("slice_{:03}.tif", nz - 1);
    let last = stack.join(&name);
    let mut decoder = tiff::decoder::Decoder::new(fs::File::open(&last).unwrap()).unwrap();
    let offset = decoder
        .get_tag_u64_vec(tiff::tags::Tag::StripOffsets)
        .unwrap()[0] as usize;
    let mut bytes = fs::read(&last).unwrap();
    bytes[offset..offset + 16].fill(0xff);
    fs::write(&last, bytes).unwrap();
    (stack, name)
}

#[test]
fn a_part_with_a_damaged_input_fails_and_the_merge_does_not_run() {
    let Some(_node) = cluster() else { return };
    let dir = submit_dir();
    let (stack, damaged) = damaged_tiff_stack(&ct(), dir.path());
    let commands = with(&documented_commands(), "N=16", "N=4");
    let commands = with(&commands, "IN=ct.nrrd", &format!("IN={}", s(&stack)));
    let jobs = submit(dir.path(), &commands);
    wait_until_done(&jobs, Duration::from_secs(90));
    let parts = accounting(&jobs.parts, 4);
    // Only part 4 holds the last plane, the damaged one.
    for i in 1..=3 {
        let r = last(&parts, &format!("{}_{i}", jobs.parts));
        assert_eq!(r.state, "COMPLETED", "part {i}: {parts:?}");
    }
    let failed = last(&parts, &format!("{}_4", jobs.parts));
    assert_eq!(
        (failed.state.as_str(), failed.exit.as_str()),
        ("FAILED", "1:0"),
        "{parts:?}"
    );
    let log = task_log(dir.path(), &jobs.parts, 4);
    let error: Vec<&str> = log
        .lines()
        .filter(|l| l.starts_with("tmc: error: "))
        .collect();
    assert!(
        error.len() == 1 && error[0].contains(&damaged),
        "part 4's log does not name the damaged slice: {log}"
    );
    // The merge never started: cancelled as its dependency cannot be met.
    let merge = accounting(&jobs.merge, 1);
    let m = last(&merge, &jobs.merge);
    assert_eq!(m.state, "CANCELLED", "{merge:?}");
    // No allocation: slurmctld may record the moment it cancelled the
    // pending job as its start (seen once in CI), but gives it no node.
    assert!(
        ["None", "Unknown"].contains(&m.start.as_str()) || m.nodes == "None assigned",
        "{m:?}"
    );
    assert!(!dir.path().join("ct.ply").exists());
    let left = names(&dir.path().join("parts"));
    assert_eq!(left, ["part-1.tmesh", "part-2.tmesh", "part-3.tmesh"]);
}

#[test]
fn scancel_of_the_array_leaves_no_part_and_no_temporary() {
    let Some(_node) = cluster() else { return };
    let (dir, _, jobs) = slow_parts_writing("ct.ply");
    slurm("scancel", &[&jobs.parts, &jobs.merge]);
    wait_until_done(&jobs, Duration::from_secs(60));
    let parts = accounting(&jobs.parts, 2);
    let first = last(&parts, &format!("{}_1", jobs.parts));
    assert_eq!(first.state, "CANCELLED", "{parts:?}");
    // tmc itself answered Slurm's SIGTERM (one error line naming it), rather
    // than being killed when Slurm's KillWait ran out.
    let log = task_log(dir.path(), &jobs.parts, 1);
    assert!(
        log.lines()
            .any(|l| l.starts_with("tmc: ") && l.contains("SIGTERM")),
        "part 1's log shows no SIGTERM handled by tmc: {log}"
    );
    let parts_dir = dir.path().join("parts");
    assert_eq!(names(&parts_dir), Vec::<String>::new(), "left in parts/");
    assert_eq!(temp_files(dir.path()), Vec::<String>::new());
    assert!(!dir.path().join("ct.ply").exists());
    assert_eq!(
        processes_in(dir.path()),
        Vec::<String>::new(),
        "still running"
    );
}

#[test]
fn a_requeued_part_still_merges_to_the_bytes_of_one_run() {
    let Some(_node) = cluster() else { return };
    let (dir, volume, jobs) = slow_parts_writing("head.tmesh");
    let task = format!("{}_1", jobs.parts);
    slurm("scontrol", &["requeue", &task]);
    // A requeued job waits two minutes before it may start again; a test
    // need not.
    let start = Instant::now();
    while !slurm("squeue", &["-h", "-t", "PD", "-j", &task, "-o", "%i"]).contains(&task) {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "{task} not requeued"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    slurm(
        "scontrol",
        &["update", &format!("JobId={task}"), "StartTime=now"],
    );
    wait_until_done(&jobs, Duration::from_secs(150));
    let parts = accounting(&jobs.parts, 2);
    let runs: Vec<&Record> = parts.iter().filter(|r| r.id == task).collect();
    assert!(
        runs.len() == 2 && runs[0].state == "REQUEUED" && runs[1].state == "COMPLETED",
        "part 1 should have run twice, requeued then completed: {parts:?}"
    );
    // The first run was stopped while it ran (its batch step got SIGTERM).
    let steps = slurm(
        "sacct",
        &[
            "-n",
            "-P",
            "-D",
            "-j",
            &task,
            "--format=JobID,State,ExitCode",
        ],
    );
    let batches: Vec<&str> = steps
        .lines()
        .filter(|l| l.starts_with(&format!("{task}.batch|")))
        .collect();
    assert!(
        batches.len() == 2 && batches[0].contains("|CANCELLED|0:15"),
        "part 1's first run was not stopped while it ran: {steps}"
    );
    let merge = accounting(&jobs.merge, 1);
    assert_eq!(last(&merge, &jobs.merge).state, "COMPLETED", "{merge:?}");
    let single = single_run(&volume, SLOW_ISO, &dir.path().join("one.tmesh"));
    let merged = fs::read(dir.path().join("head.tmesh")).expect("the merge wrote head.tmesh");
    assert!(
        merged == single,
        "the merged head.tmesh differs from a single run"
    );
    assert_eq!(
        names(&dir.path().join("parts")),
        ["part-1.tmesh", "part-2.tmesh"]
    );
}

/// The job script's arithmetic, without Slurm: the environment of an
/// allocation given by hand, and a `tmc` on `PATH` that prints its
/// arguments.
#[test]
fn the_part_script_takes_threads_and_memory_from_the_allocation() {
    let dir = tempfile::tempdir().unwrap();
    let path = fake_tmc(dir.path(), "echo \"$@\"");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm/tmc-parts.sbatch");
    let run = |env: &[(&str, &str)]| {
        let out = Command::new("bash")
            .arg(&script)
            .current_dir(dir.path())
            .env_clear()
            .env("PATH", &path)
            .envs([("N", "2"), ("IN", "ct.nrrd"), ("ISO", "550")])
            .env("SLURM_ARRAY_TASK_ID", "2")
            .envs(env.iter().copied())
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        String::from_utf8(out.stdout).unwrap()
    };
    let args = |rest: &str| {
        format!(
            "extract ct.nrrd --iso 550 {rest} --progress lines --part 2/2 -o parts/part-2.tmesh\n"
        )
    };
    // --cpus-per-task=4 --mem=4G
    let per_node = [("SLURM_CPUS_PER_TASK", "4"), ("SLURM_MEM_PER_NODE", "4096")];
    assert_eq!(run(&per_node), args("--threads 4 --max-memory 3584M"));
    // --cpus-per-task=3 --mem-per-cpu=1000M: 3000 MiB on the node
    let per_cpu = [
        ("SLURM_CPUS_PER_TASK", "3"),
        ("SLURM_CPUS_ON_NODE", "3"),
        ("SLURM_MEM_PER_CPU", "1000"),
    ];
    assert_eq!(run(&per_cpu), args("--threads 3 --max-memory 2625M"));
    // --mem=0 (the whole node), and no allocation at all: tmc's defaults
    let whole = [("SLURM_CPUS_PER_TASK", "2"), ("SLURM_MEM_PER_NODE", "0")];
    assert_eq!(run(&whole), args("--threads 2"));
    assert_eq!(run(&[]), args("--threads 0"));
}

/// The job scripts with `LABELS` (a label map), without Slurm: the array
/// tasks' environment given by hand and the built `tmc` on `PATH`. Every
/// part and the merge succeed, one mesh per label equal byte for byte to
/// one run's; `ISO` and `LABELS` together are refused. The scripts had no
/// way to pass `--labels`: with `EXTRA=--labels` every part was refused.
#[test]
fn the_job_scripts_split_and_merge_a_label_map() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = synth(d, "head", "24,20,30", "u8", "map.npy");
    let run = |script: &str, env: &[(&str, &str)]| {
        let given = [("N", "3"), ("IN", s(&input)), ("LABELS", "all")];
        job_script(d, script, &[&given[..], env].concat())
    };
    for task in ["1", "2", "3"] {
        let out = run("tmc-parts.sbatch", &[("SLURM_ARRAY_TASK_ID", task)]);
        assert!(out.status.success(), "{out:?}");
    }
    for dir in ["one", "merged"] {
        fs::create_dir(d.join(dir)).unwrap();
    }
    let out = run("tmc-merge.sbatch", &[("OUT", "merged/{label}.ply")]);
    assert!(out.status.success(), "{out:?}");
    let one = d.join("one/{label}.ply");
    let out = tmc(&["extract", s(&input), "--labels", "all", "-q", "-o", s(&one)]);
    assert!(out.status.success(), "{out:?}");
    let labels = names(&d.join("one"));
    assert!(labels.len() > 1, "{labels:?}");
    assert_eq!(names(&d.join("merged")), labels);
    for name in labels {
        assert_eq!(
            fs::read(d.join("merged").join(&name)).unwrap(),
            fs::read(d.join("one").join(&name)).unwrap(),
            "{name}"
        );
    }
    let both = run(
        "tmc-parts.sbatch",
        &[("SLURM_ARRAY_TASK_ID", "1"), ("ISO", "3")],
    );
    assert_eq!(both.status.code(), Some(2), "{both:?}");
}

/// Runs `scripts/slurm/SCRIPT` with bash in `dir` as an array task or the
/// merge job would run it, without Slurm: `env` the whole environment but
/// `PATH`, which has the built `tmc` first.
fn job_script(dir: &Path, script: &str, env: &[(&str, &str)]) -> std::process::Output {
    let script = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scripts/slurm")
        .join(script);
    let bin = Path::new(tmc_path()).parent().unwrap().to_path_buf();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    Command::new("bash")
        .arg(script)
        .current_dir(dir)
        .env_clear()
        .env("PATH", &path)
        .envs(env.iter().copied())
        .output()
        .unwrap()
}

/// The merge job merges parts 1 to N of its run, without Slurm as above:
/// the parts of an earlier run of the same input with more parts, left in
/// `parts/`, made it fail ("part counts (3 vs 4) differ", for an
/// isosurface and a label map) though every part of the run was there.
#[test]
fn the_merge_script_takes_the_n_parts_of_its_run() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = synth(d, "head", "24,20,30", "u8", "map.npy");
    let cases: [(&str, &str, &str); 2] =
        [("ISO", "100", "m.ply"), ("LABELS", "all", "{label}.ply")];
    for (what, value, out) in cases {
        for dir in ["parts", "one", "merged"] {
            let _ = fs::remove_dir_all(d.join(dir));
        }
        // The earlier run of 4 parts, then this one of 3.
        for n in ["4", "3"] {
            for task in 1..=n.parse().unwrap() {
                let task = task.to_string();
                let env = [
                    ("N", n),
                    ("IN", s(&input)),
                    (what, value),
                    ("SLURM_ARRAY_TASK_ID", &task),
                ];
                let done = job_script(d, "tmc-parts.sbatch", &env);
                assert!(done.status.success(), "{done:?}");
            }
        }
        for dir in ["one", "merged"] {
            fs::create_dir(d.join(dir)).unwrap();
        }
        let merged = d.join("merged").join(out);
        let env = [("N", "3"), (what, value), ("OUT", s(&merged))];
        let done = job_script(d, "tmc-merge.sbatch", &env);
        assert!(done.status.success(), "{what}: {done:?}");
        let one = d.join("one").join(out);
        let option = format!("--{}", what.to_lowercase());
        let done = tmc(&["extract", s(&input), &option, value, "-q", "-o", s(&one)]);
        assert!(done.status.success(), "{done:?}");
        let meshes = names(&d.join("one"));
        assert_eq!(names(&d.join("merged")), meshes, "{what}");
        for name in meshes {
            let read = |dir: &str| fs::read(d.join(dir).join(&name)).unwrap();
            assert!(read("merged") == read("one"), "{what}: {name}");
        }
    }
}

/// The command the part script prints at the top of the task's log is the
/// one it runs, as a shell reads it back: an input or parts directory
/// whose name has a space (`IN='my scans/c t.nrrd'`), and the label
/// parts' braces. It was the words joined by spaces, so that pasting it
/// to run a part again read `my`, `scans/c` and `t.nrrd`.
#[test]
fn the_part_script_prints_the_command_it_runs() {
    let dir = tempfile::tempdir().unwrap();
    // A tmc that prints its arguments one a line.
    let path = fake_tmc(dir.path(), "printf '%s\\n' \"$@\"");
    for what in [("ISO", "550"), ("LABELS", "1,4")] {
        let env = [
            ("PATH", path.as_str()),
            ("N", "2"),
            ("SLURM_ARRAY_TASK_ID", "1"),
            ("IN", "my scans/c t.nrrd"),
            ("PARTS", "the parts"),
            ("EXTRA", "--close"),
            what,
        ];
        let bash = |args: &[&std::ffi::OsStr]| {
            Command::new("bash")
                .args(args)
                .current_dir(dir.path())
                .env_clear()
                .envs(env)
                .output()
                .unwrap()
        };
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm/tmc-parts.sbatch");
        let out = bash(&[script.as_os_str()]);
        assert!(out.status.success(), "{out:?}");
        let ran = String::from_utf8(out.stdout).unwrap();
        let stderr = String::from_utf8(out.stderr).unwrap();
        let printed = stderr
            .lines()
            .find_map(|l| l.strip_prefix("tmc-parts.sbatch: "))
            .unwrap_or_else(|| panic!("no command in {stderr}"));
        // The printed command run by a shell, with the same tmc.
        let again = bash(&["-c".as_ref(), printed.as_ref()]);
        assert!(again.status.success(), "{printed}: {again:?}");
        assert_eq!(String::from_utf8(again.stdout).unwrap(), ran, "{printed}");
        assert!(ran.lines().any(|a| a == "my scans/c t.nrrd"), "{ran}");
    }
}

/// A `PATH` whose first directory, `dir/bin`, holds a `tmc` that is the sh
/// script `body`.
fn fake_tmc(dir: &Path, body: &str) -> String {
    use std::os::unix::fs::PermissionsExt;
    let bin = dir.join("bin");
    fs::create_dir(&bin).unwrap();
    fs::write(bin.join("tmc"), format!("#!/bin/sh\n{body}\n")).unwrap();
    fs::set_permissions(bin.join("tmc"), fs::Permissions::from_mode(0o755)).unwrap();
    format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    )
}
