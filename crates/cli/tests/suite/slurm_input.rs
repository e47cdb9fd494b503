//! `study --slurm` refuses bad options before it writes anything, with or without a
//! cluster: a malformed time limit, bad memory, and `--submit` where sbatch is missing.

use crate::run_cli;
use run_cli::utf8;
use std::path::Path;
use std::process::Command;

#[test]
fn malformed_options_are_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let out = dir.path().join("study");
    for (flags, needle) in [
        (
            vec!["--time", "25:99"],
            "--time: time limit '25:99': seconds 99 must be below 60",
        ),
        (vec!["--mem", "lots"], "--mem 'lots'"),
        (vec!["--throttle", "0"], "--throttle 0"),
    ] {
        let mut args = vec![
            "study",
            "fan2023",
            "--quick",
            "--out",
            utf8(&out),
            "--slurm",
        ];
        args.extend(flags.iter().copied());
        let output = Command::new(env!("CARGO_BIN_EXE_hopperflow"))
            .args(&args)
            .output()
            .expect("runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{flags:?}: {stderr}");
        assert!(stderr.contains(needle), "{flags:?}: {stderr}");
        assert!(!out.exists(), "{flags:?}: the study folder was created");
    }
}

#[test]
fn submit_without_sbatch_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let out = dir.path().join("study");
    // A PATH with no sbatch (nor sinfo) on it.
    let empty = dir.path().join("bin");
    std::fs::create_dir(&empty).expect("bin");
    let output = Command::new(env!("CARGO_BIN_EXE_hopperflow"))
        .args([
            "study",
            "fan2023",
            "--quick",
            "--out",
            utf8(&out),
            "--slurm",
            "--submit",
        ])
        .env("PATH", &empty)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--submit needs sbatch"), "{stderr}");
    assert!(!out.exists(), "the study folder was created");

    // Without --submit the scripts are written, and nothing is run.
    let output = Command::new(env!("CARGO_BIN_EXE_hopperflow"))
        .args([
            "study",
            "fan2023",
            "--quick",
            "--out",
            utf8(&out),
            "--slurm",
        ])
        .env("PATH", &empty)
        .output()
        .expect("runs");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let tasks = std::fs::read_to_string(out.join("slurm/tasks-1.txt")).expect("task list");
    assert_eq!(
        tasks.lines().count(),
        6,
        "one task per case of the quick study"
    );
    let script = std::fs::read_to_string(out.join("slurm/array-1.sh")).expect("script");
    assert!(script.contains("#SBATCH --array=0-5"), "{script}");
    assert!(!out.join("results.csv").exists(), "nothing ran");
}

#[test]
fn one_task_runs_one_case_and_collect_writes_the_local_table() {
    // The array's pieces without a scheduler: every task by hand, then the collection,
    // give the results.csv of the same study run here.
    let dir = tempfile::tempdir().expect("temporary directory");
    let (local, tasks) = (dir.path().join("local"), dir.path().join("tasks"));
    let hf = |args: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_hopperflow"))
            .args(args)
            .env("PATH", dir.path()) // no Slurm tools: the writing must not need them
            .output()
            .expect("runs");
        assert!(
            output.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        output
    };
    // Two cases of the quick study's hopper cut to 300 spheres and their first 40 % of
    // discharge: the test is about which case runs where, and every case still fills,
    // opens and measures a rate.
    let sweep = dir.path().join("two.toml");
    std::fs::write(
        &sweep,
        "version = 1\nname = \"two-outlets\"\n[base]\nversion = 1\nseed = 2023\n\
         [base.geometry]\nwidth = 0.06\nheight = 0.15\n[base.particles]\ncount = 300\n\
         [base.protocol]\nmax_settle_time = 1.0\nstop_fraction = 0.4\n\
         [base.measure]\nsteady_end_fraction = 0.4\n\
         [base.output]\ncheckpoint_interval = 0.0\nvtu_interval = 0.0\n\
         [[axes]]\nkey = \"geometry.outlet_width\"\nvalues = [0.018, 0.03]\nlabel = \"D\"\n",
    )
    .expect("the sweep file");
    let reduced = ["study", utf8(&sweep), "--no-pictures", "--out"];
    let mut local_run = reduced.to_vec();
    local_run.push(utf8(&local));
    hf(&local_run);
    let mut base = reduced.to_vec();
    base.push(utf8(&tasks));
    let mut write = base.to_vec();
    write.push("--slurm");
    hf(&write);
    let list = tasks.join("slurm/tasks-1.txt");
    for index in 0..2 {
        let index = index.to_string();
        let mut task = base.to_vec();
        task.extend(["--task-list", utf8(&list), "--task-index", &index]);
        hf(&task);
    }
    let mut collect = base.to_vec();
    collect.push("--collect");
    hf(&collect);
    let read = |d: &Path| std::fs::read(d.join("results.csv")).expect("results.csv");
    assert!(
        read(&local) == read(&tasks),
        "collected table differs from the local one"
    );
}
