//! The README and the guides in doc/ say only what runs. Checked here,
//! against the repository itself (the reference for each check is named
//! with it):
//! - the README is a front door: at most 150 lines, it starts with the two
//!   commands (`make run`, `make test`), and every guide it names exists;
//! - every repository path written in backticks exists (the file tree);
//! - every command of a ```sh block names what exists: `make` targets are
//!   rules of the Makefile, `cargo bench --bench X` a bench of Cargo.toml,
//!   `cargo test --test X` a file tests/X.rs, `target/release/native/P` a
//!   program the Makefile builds, `sbatch F` a file, `rodkit::T` a target of
//!   the CMake package template, `pkg-config … P` a package `make install`
//!   writes;
//! - the C and Fortran blocks and the build-tree compile lines of
//!   doc/using.md are run: each C block is compiled and linked against the
//!   library by the guide's own `gcc` lines and must exit 0; each Fortran
//!   block with its `gfortran` lines, likewise.

#[path = "support/native_build.rs"]
mod native_build;

use native_build::{check, ROOT};
use std::path::Path;
use std::process::Command;

/// README.md and every guide in doc/ (physics.md included: its paths must
/// exist too), with their text.
fn documents() -> Vec<(String, String)> {
    let mut docs = vec![("README.md".to_string(), read("README.md"))];
    let mut guides: Vec<_> = std::fs::read_dir(Path::new(ROOT).join("doc"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".md"))
        .collect();
    guides.sort();
    for g in guides {
        let path = format!("doc/{g}");
        docs.push((path.clone(), read(&path)));
    }
    docs
}

fn read(path: &str) -> String {
    std::fs::read_to_string(Path::new(ROOT).join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The fenced blocks of a Markdown text: (language, body).
fn blocks(text: &str) -> Vec<(String, String)> {
    let mut out = vec![];
    let mut current: Option<(String, String)> = None;
    for line in text.lines() {
        let t = line.trim_start();
        if let Some(rest) = t.strip_prefix("```") {
            match current.take() {
                Some(b) => out.push(b),
                None => current = Some((rest.trim().to_string(), String::new())),
            }
        } else if let Some((_, body)) = current.as_mut() {
            body.push_str(line);
            body.push('\n');
        }
    }
    out
}

/// The prefixes of repository paths as the documents write them.
const ROOTS: [&str; 11] = [
    "c_examples/",
    "fortran_examples/",
    "tests/",
    "benches/",
    "src/",
    "doc/",
    "include/",
    "cmake/",
    ".ci/",
    "codegen/",
    "tests/downstream/",
];

/// Backticked tokens outside code blocks that look like repository paths.
fn backticked_paths(text: &str) -> Vec<String> {
    let mut prose = String::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if !fenced {
            prose.push_str(line);
            prose.push('\n');
        }
    }
    let mut out = vec![];
    for (i, part) in prose.split('`').enumerate() {
        if i % 2 == 0 {
            continue;
        }
        for word in part.split_whitespace() {
            let w = word.trim_end_matches([',', ';', ':', '.', ')']).trim_start_matches('(');
            let top = ["Makefile", "Cargo.toml", "CHANGELOG.md", "CITATION.cff", "LICENSE-MIT", "LICENSE-APACHE"];
            if ROOTS.iter().any(|r| w.starts_with(r)) || top.contains(&w) {
                out.push(w.to_string());
            }
        }
    }
    out
}

/// A path as written, or the fixed part before a pattern (`*`, `{`, `<`):
/// that part must exist.
fn exists(path: &str) -> bool {
    let fixed = match path.find(['*', '{', '<', '…']) {
        Some(i) => &path[..path[..i].rfind('/').map_or(0, |j| j + 1)],
        None => path,
    };
    Path::new(ROOT).join(fixed.trim_end_matches(':')).exists()
}

#[test]
fn readme_is_a_front_door() {
    let readme = read("README.md");
    let lines = readme.lines().count();
    assert!(lines <= 150, "README.md has {lines} lines (at most 150)");
    // The two commands come first: the first code block holds them.
    let first = blocks(&readme).into_iter().next().expect("a code block").1;
    let commands: Vec<&str> = first.lines().map(|l| l.split('#').next().unwrap().trim()).collect();
    assert_eq!(commands, ["make run", "make test"], "the README's first block");
    for guide in ["doc/tubes.md", "doc/rods.md", "doc/dna.md", "doc/cluster.md", "doc/using.md"] {
        let name = guide.trim_start_matches("doc/");
        assert!(readme.contains(guide) || readme.contains(name), "README does not point to {guide}");
        assert!(Path::new(ROOT).join(guide).exists(), "{guide} missing");
    }
    // User documents speak of rodkit, not of issues (the CHANGELOG keeps history).
    for (name, text) in documents() {
        for (n, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            assert!(
                !(lower.contains("issue ") && lower.split("issue ").skip(1).any(|r| r.starts_with(char::is_numeric))),
                "{name}:{}: names an issue: {line}",
                n + 1
            );
        }
    }
}

/// The sources' comments say why, not when: no issue number and no date
/// (the history is in CHANGELOG.md and benches/README.md). Reference: the
/// project's layout rules.
#[test]
fn sources_name_no_issue_and_no_date() {
    fn walk(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let mut files = vec![];
    walk(&Path::new(ROOT).join("src"), &mut files);
    assert!(files.len() > 50, "{} source files", files.len());
    let mut found = vec![];
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        // Lines joined so that a number wrapped onto the next comment line counts.
        let joined = text
            .lines()
            .map(|l| l.trim_start().trim_start_matches('/').trim_start_matches('!'))
            .collect::<Vec<_>>()
            .join(" ");
        let lower = joined.to_lowercase();
        for (i, _) in lower.match_indices("issue ") {
            if lower[i + 6..].trim_start().starts_with(char::is_numeric) {
                found.push(format!("{}: issue {}", f.display(), &lower[i + 6..(i + 16).min(lower.len())]));
            }
        }
        let b = joined.as_bytes();
        for i in 0..b.len().saturating_sub(10) {
            let d = |k: usize| b[i + k].is_ascii_digit();
            if b[i..i + 3] == *b"202" && d(3) && b[i + 4] == b'-' && d(5) && d(6) && b[i + 7] == b'-' && d(8) && d(9) {
                found.push(format!("{}: date {}", f.display(), &joined[i..i + 10]));
            }
        }
    }
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn every_path_named_exists() {
    let mut missing = vec![];
    for (name, text) in documents() {
        for p in backticked_paths(&text) {
            if !exists(&p) {
                missing.push(format!("{name}: `{p}`"));
            }
        }
    }
    assert!(missing.is_empty(), "paths that do not exist:\n{}", missing.join("\n"));
}

/// The rules of the Makefile (`name:` at the start of a line, and the
/// programs it builds as `$(BUILD)/name:`).
fn make_rules() -> (Vec<String>, Vec<String>) {
    let makefile = read("Makefile");
    let mut targets = vec![];
    let mut programs = vec![];
    for line in makefile.lines() {
        let Some((head, _)) = line.split_once(':') else { continue };
        if head.contains('=') || head.starts_with(['\t', ' ', '#']) {
            continue;
        }
        for word in head.split_whitespace() {
            if let Some(p) = word.strip_prefix("$(BUILD)/") {
                programs.push(p.to_string());
            } else if !word.contains('$') {
                targets.push(word.to_string());
            }
        }
    }
    (targets, programs)
}

#[test]
fn every_command_names_what_exists() {
    let (targets, programs) = make_rules();
    let cargo = read("Cargo.toml");
    let benches: Vec<&str> = cargo
        .split("[[bench]]")
        .skip(1)
        .filter_map(|b| b.lines().find_map(|l| l.trim().strip_prefix("name = \"")).map(|n| n.trim_end_matches('"')))
        .collect();
    let cmake_package = read("cmake/rodkitConfig.cmake.in");
    let makefile = read("Makefile");
    let mut wrong = vec![];
    for (name, text) in documents() {
        for (lang, body) in blocks(&text) {
            if lang == "cmake" {
                for t in body.split("rodkit::").skip(1) {
                    let target: String = t.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                    if !cmake_package.contains(&format!("add_library(rodkit::{target} ")) {
                        wrong.push(format!("{name}: CMake target rodkit::{target}"));
                    }
                }
            }
            if lang != "sh" {
                continue;
            }
            let joined = body.replace("\\\n", " ");
            for line in joined.lines() {
                let command = line.split(" #").next().unwrap().trim();
                let words: Vec<&str> = command.split_whitespace().collect();
                let mut check = |ok: bool, what: String| {
                    if !ok {
                        wrong.push(format!("{name}: {what} in `{command}`"));
                    }
                };
                for (i, w) in words.iter().enumerate() {
                    let next = words.get(i + 1).copied().unwrap_or("");
                    match *w {
                        "make" => {
                            let mut k = i + 1;
                            while let Some(arg) = words.get(k) {
                                if *arg == "&&" || *arg == "|" || *arg == ";" {
                                    break;
                                }
                                if *arg == "-C" {
                                    k += 2;
                                    continue;
                                }
                                if !arg.contains('=') && !arg.starts_with('-') {
                                    check(targets.iter().any(|t| t == arg), format!("make target `{arg}`"));
                                }
                                k += 1;
                            }
                        }
                        "--bench" => check(benches.contains(&next), format!("bench `{next}`")),
                        "--test" => check(
                            Path::new(ROOT).join("tests").join(format!("{next}.rs")).exists(),
                            format!("test `{next}`"),
                        ),
                        "sbatch" => check(exists(next), format!("batch file `{next}`")),
                        "pkg-config" => {
                            for p in words[i + 1..].iter().take_while(|a| !a.starts_with(')')) {
                                let p = p.trim_end_matches(')');
                                if p.starts_with("rodkit") {
                                    check(makefile.contains(&format!("{p}.pc")), format!("pkg-config package `{p}`"));
                                }
                            }
                        }
                        _ => {
                            if let Some(p) = w.strip_prefix("target/release/native/") {
                                check(programs.iter().any(|q| q == p), format!("program `{p}`"));
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(wrong.is_empty(), "commands that name what does not exist:\n{}", wrong.join("\n"));
}

/// doc/using.md's C and Fortran blocks, built with its own build-tree lines
/// (`gcc … prog.c …`, `gfortran … prog.f90 …`) in a scratch folder that sees
/// the repository's include/ and target/, and run: each must exit 0. A C
/// block that is a fragment (no `main`) is wrapped in one.
#[test]
fn code_in_the_guides_compiles_and_runs() {
    native_build::build_lib_and_make(&["lib"]);
    let using = read("doc/using.md");
    let all = blocks(&using);
    let compile: Vec<String> = all
        .iter()
        .filter(|(l, _)| l == "sh")
        .flat_map(|(_, b)| b.replace("\\\n", " ").lines().map(str::to_string).collect::<Vec<_>>())
        .filter(|l| l.contains("prog.c") || l.contains("prog.f90") || l.contains("rodkit.f90 -J build"))
        .collect();
    assert!(compile.iter().any(|l| l.starts_with("gcc")), "doc/using.md has no gcc line for prog.c");
    assert!(compile.iter().any(|l| l.starts_with("gfortran")), "doc/using.md has no gfortran line for prog.f90");
    let mut programs: Vec<(&str, String)> = vec![];
    for (_, text) in documents() {
        for (lang, body) in blocks(&text) {
            match lang.as_str() {
                "c" if body.contains("main(") => programs.push(("c", body)),
                "c" => {
                    let (includes, rest): (Vec<&str>, Vec<&str>) =
                        body.lines().partition(|l| l.trim_start().starts_with("#include"));
                    let source = format!(
                        "#include <stdio.h>\n{}\nint main(void) {{\n{}\n    return st < 0;\n}}\n",
                        includes.join("\n"),
                        rest.join("\n")
                    );
                    programs.push(("c", source));
                }
                "fortran" => programs.push(("fortran", body)),
                _ => {}
            }
        }
    }
    assert!(programs.iter().any(|(k, _)| *k == "c") && programs.iter().any(|(k, _)| *k == "fortran"));
    let scratch = std::env::temp_dir().join(format!("rodkit_docs_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    std::fs::create_dir_all(scratch.join("build")).unwrap();
    for d in ["include", "target"] {
        std::os::unix::fs::symlink(Path::new(ROOT).join(d), scratch.join(d)).unwrap();
    }
    for (k, (kind, source)) in programs.iter().enumerate() {
        let file = if *kind == "c" { "prog.c" } else { "prog.f90" };
        std::fs::write(scratch.join(file), source).unwrap();
        let _ = std::fs::remove_file(scratch.join("a.out"));
        for line in compile.iter().filter(|l| l.contains(file) || (*kind == "fortran" && l.contains("-J build"))) {
            let out = Command::new("bash").arg("-c").arg(line).current_dir(&scratch).output().unwrap();
            check(out, &format!("block {k} ({kind}): `{line}`\n{source}"));
            if line.contains(file) {
                let run = Command::new(scratch.join("a.out")).current_dir(&scratch).output().unwrap();
                check(run, &format!("block {k} ({kind}) built by `{line}`\n{source}"));
            }
        }
    }
    std::fs::remove_dir_all(&scratch).unwrap();
}
