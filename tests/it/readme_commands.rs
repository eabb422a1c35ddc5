//! Every `dalembert` command in the README's `sh` blocks runs as written, with the built
//! binary first on PATH, and exits with the status the README states (`# exit N` in the
//! line's comment) or 0. The lines run in order in one scratch directory (so a file that one
//! line writes, such as `traj.csv`, is there for the next), which holds a copy of
//! `examples/scenes/` for the lines that read a scene file.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The lines of the README's `sh` blocks that run the `dalembert` command, each with its
/// expected exit status.
fn commands(readme: &str) -> Vec<(String, i32)> {
    let mut out = Vec::new();
    let mut in_sh = false;
    for line in readme.lines() {
        if line.starts_with("```") {
            in_sh = line.trim() == "```sh";
            continue;
        }
        if !in_sh {
            continue;
        }
        let (cmd, comment) = match line.find("  #") {
            Some(i) => (
                line[..i].trim(),
                line[i..].trim_start().trim_start_matches('#'),
            ),
            None => (line.trim(), ""),
        };
        let runs_dalembert = cmd.starts_with("dalembert ") || cmd.contains("| dalembert ");
        if !runs_dalembert {
            continue;
        }
        let status = comment
            .trim()
            .strip_prefix("exit ")
            .map(|s| {
                let digits: String = s.chars().take_while(|c| c.is_ascii_digit()).collect();
                digits.parse().expect("`# exit N` names a status")
            })
            .unwrap_or(0);
        out.push((cmd.to_string(), status));
    }
    out
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        if entry.file_type().unwrap().is_file() {
            std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    }
}

#[test]
fn every_readme_command_runs_as_written() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let cmds = commands(&readme);
    // the README shows a flow, a step, a float trajectory and its check, a batch query and
    // a scene file's commands
    assert!(cmds.len() >= 6, "{cmds:?}");

    let bin = PathBuf::from(env!("CARGO_BIN_EXE_dalembert"));
    let path = std::env::join_paths(std::iter::once(bin.parent().unwrap().to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .unwrap();
    let dir = std::env::temp_dir().join(format!("dalembert-readme-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    copy_dir(&root.join("examples/scenes"), &dir.join("examples/scenes"));

    for (cmd, status) in &cmds {
        let out = Command::new("sh")
            .arg("-c")
            .arg(cmd)
            .current_dir(&dir)
            .env("PATH", &path)
            .output()
            .unwrap();
        assert_eq!(
            out.status.code(),
            Some(*status),
            "`{cmd}`\nstdout: {}\nstderr: {}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        // an answer is printed exactly when the command answered (exit 0 or 1)
        if *status <= 1 && !cmd.contains('>') {
            assert!(!out.stdout.is_empty(), "`{cmd}` printed nothing");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_command_reader_finds_statuses_and_pipes() {
    let text = "```sh\ncargo test\ndalembert a --x 1   # exit 1: why\necho '{}' | dalembert batch\n```\n```toml\ndalembert = 1\n```\n";
    assert_eq!(
        commands(text),
        vec![
            ("dalembert a --x 1".to_string(), 1),
            ("echo '{}' | dalembert batch".to_string(), 0)
        ]
    );
}
