//! Architecture guards: checks on the workspace's structure made by reading
//! its source files (no compiler involved), so that the layering and the size
//! of the code stay where the design wants them.
//!
//! * `wgpu_backend_does_not_depend_on_the_cpu_backend` — `himmel-wgpu` takes
//!   what it needs from `himmel-skymodel`, not from the CPU renderer;
//! * `source_files_stay_short` — no `.rs` file of `backend-wgpu/src` or
//!   `skymodel/src` has more than [`MAX_FILE_LINES`] lines outside
//!   `#[cfg(test)]` modules;
//! * `functions_stay_short` — no `fn` there spans more than [`MAX_FN_LINES`]
//!   lines;
//! * `skymodel_modules_form_no_cycle` — the `crate::` imports between the
//!   top-level modules of `himmel-skymodel` form no cycle.
//!
//! Each failure lists every offender as `path:line: …`, a to-do list.
//!
//! How the sources are read (see the `helper_*` tests at the end, which keep
//! the checker from passing silently):
//! * comments (`//…`, nested `/* … */`), string literals (`"…"`, `b"…"`,
//!   raw `r#"…"#`) and char literals (`'{'`, `'\''`, `'\u{7b}'`; lifetimes
//!   and labels such as `'a` are left alone) are blanked out, newlines kept,
//!   before anything else looks at the code;
//! * a `#[cfg(test)]` module is the attribute, any further attributes, then
//!   `[pub[(…)]] mod name {` up to its matching `}` (or `mod name;`, whose
//!   file is then skipped altogether; a file with `#![cfg(test)]` is skipped
//!   too); these lines are neither counted nor searched;
//! * a function is a `fn name` item from its line to the `}` matching the
//!   first `{` met at bracket depth 0 after the name; one whose signature
//!   ends in `;` first (a trait method without a default body, an `extern`
//!   declaration) has no body and is not measured;
//! * a skymodel module is `skymodel/src/x.rs` or the folder `skymodel/src/x/`;
//!   its edges are the `crate::y` paths (also `crate::{y::…, z}` groups, and
//!   `crate::Name` where `lib.rs` has `use y::Name`) in its files.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The most lines a source file may have, `#[cfg(test)]` modules not counted.
const MAX_FILE_LINES: usize = 800;
/// The most lines a function may span, from its `fn` line to its closing brace.
const MAX_FN_LINES: usize = 150;
/// The folders whose `.rs` files (recursively) are held to the two limits.
const LENGTH_CHECKED_DIRS: &[&str] = &["backend-wgpu/src", "skymodel/src"];
/// Generated files (tables written by a tool, not by hand), exempt from
/// [`MAX_FILE_LINES`] and [`MAX_FN_LINES`]. Paths relative to the workspace
/// root with `/` separators, e.g. `"skymodel/src/moon/albedo_table.rs"`; name
/// the generator in a comment next to each entry. Every entry must exist: a
/// stale one fails `source_files_stay_short`. Empty for now: no generated
/// tables live in the checked folders.
const GENERATED_FILES: &[&str] = &[];

// ---------------------------------------------------------------------------
// The tests.

#[test]
fn wgpu_backend_does_not_depend_on_the_cpu_backend() {
    let mut offenders = Vec::new();

    let manifest = "backend-wgpu/Cargo.toml";
    for (line, text) in normal_dependency_entries(&read(manifest), "himmel-cpu") {
        offenders.push(format!("{manifest}:{line}: {text}"));
    }

    for file in load_sources("backend-wgpu/src") {
        for (k, raw) in file.raw_lines.iter().enumerate() {
            if !file.test_line[k] && raw.contains("himmel_cpu") {
                offenders.push(format!("{}:{}: {}", file.path, k + 1, excerpt(raw)));
            }
        }
    }

    assert!(
        offenders.is_empty(),
        "himmel-wgpu must not depend on himmel-cpu (a [dev-dependencies] entry for tests \
         is fine); {} offending line(s):\n  {}\n",
        offenders.len(),
        offenders.join("\n  ")
    );
}

#[test]
fn source_files_stay_short() {
    let mut offenders = Vec::new();
    for stale in GENERATED_FILES
        .iter()
        .filter(|p| !workspace_root().join(p).is_file())
    {
        offenders.push(format!(
            "{stale}: listed in GENERATED_FILES but does not exist"
        ));
    }
    for file in length_checked_sources() {
        let counted = file.test_line.iter().filter(|t| !**t).count();
        if counted <= MAX_FILE_LINES {
            continue;
        }
        // The first line past the limit, to point at.
        let mut seen = 0;
        let first_over = file
            .test_line
            .iter()
            .position(|t| {
                seen += usize::from(!*t);
                seen > MAX_FILE_LINES
            })
            .map_or(1, |k| k + 1);
        let in_tests = file.raw_lines.len() - counted;
        offenders.push(format!(
            "{}:{first_over}: {counted} lines ({} in all, {in_tests} in #[cfg(test)] modules), \
             {} over the limit",
            file.path,
            file.raw_lines.len(),
            counted - MAX_FILE_LINES
        ));
    }
    assert!(
        offenders.is_empty(),
        "{} source file(s) exceed {MAX_FILE_LINES} lines not counting #[cfg(test)] modules \
         (split them; generated tables go in GENERATED_FILES):\n  {}\n",
        offenders.len(),
        offenders.join("\n  ")
    );
}

#[test]
fn functions_stay_short() {
    let mut offenders = Vec::new();
    let mut measured = 0;
    for file in length_checked_sources() {
        let spans = functions(&file.code)
            .unwrap_or_else(|e| panic!("architecture checker cannot read {}: {e}", file.path));
        measured += spans.len();
        for f in spans.iter().filter(|f| f.lines() > MAX_FN_LINES) {
            offenders.push(format!(
                "{}:{}: fn {} spans {} lines (to line {})",
                file.path,
                f.first_line,
                f.name,
                f.lines(),
                f.last_line
            ));
        }
    }
    assert!(measured > 0, "the checker found no functions at all");
    assert!(
        offenders.is_empty(),
        "{} function(s) span more than {MAX_FN_LINES} lines (outside #[cfg(test)] modules):\n  {}\n",
        offenders.len(),
        offenders.join("\n  ")
    );
}

#[test]
fn skymodel_modules_form_no_cycle() {
    let graph = skymodel_import_graph();
    assert!(
        graph.modules.contains("moon") && graph.modules.contains("state"),
        "the checker did not find the skymodel modules: {:?}",
        graph.modules
    );
    let adjacency = graph.adjacency();
    let cycles = elementary_cycles(&adjacency, 100);
    if cycles.is_empty() {
        return;
    }

    let mut on_cycle = BTreeSet::new();
    for cycle in &cycles {
        for pair in cycle.windows(2) {
            on_cycle.insert((pair[0].clone(), pair[1].clone()));
        }
    }
    let mut msg = format!(
        "the modules of himmel-skymodel import each other in {} cycle(s){}:\n",
        cycles.len(),
        if cycles.len() == 100 {
            " (first 100 shown)"
        } else {
            ""
        }
    );
    for cycle in &cycles {
        msg += &format!("  {} (length {})\n", cycle.join(" -> "), cycle.len() - 1);
    }
    msg += "the imports that make up these cycles (break each cycle at one edge):\n";
    for edge in &on_cycle {
        let evidence = &graph.edges[edge];
        msg += &format!(
            "  {} -> {} ({} mention(s)):\n",
            edge.0,
            edge.1,
            evidence.len()
        );
        for e in evidence {
            msg += &format!("    {e}\n");
        }
    }
    panic!("{msg}");
}

// ---------------------------------------------------------------------------
// Reading the workspace.

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn read(rel: &str) -> String {
    let path = workspace_root().join(rel);
    fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// The `.rs` files under `rel_dir` (recursively), workspace-relative with
/// `/` separators, sorted.
fn rust_files(rel_dir: &str) -> Vec<String> {
    fn walk(dir: &Path, rel: &str, out: &mut Vec<String>) {
        let entries = fs::read_dir(dir).unwrap_or_else(|e| panic!("cannot list {rel}: {e}"));
        for entry in entries {
            let entry = entry.unwrap();
            let name = entry.file_name().to_string_lossy().into_owned();
            let child = format!("{rel}/{name}");
            let kind = entry.file_type().unwrap();
            if kind.is_dir() {
                walk(&entry.path(), &child, out);
            } else if name.ends_with(".rs") {
                out.push(child);
            }
        }
    }
    let mut out = Vec::new();
    walk(&workspace_root().join(rel_dir), rel_dir, &mut out);
    out.sort();
    assert!(!out.is_empty(), "no .rs files under {rel_dir}");
    out
}

/// One source file, read for the checks.
struct SourceFile {
    /// Workspace-relative path.
    path: String,
    /// The file as written, line by line.
    raw_lines: Vec<String>,
    /// Whether each line belongs to a `#[cfg(test)]` module.
    test_line: Vec<bool>,
    /// Comments, literals and `#[cfg(test)]` modules blanked out.
    code: Code,
    /// Files of `#[cfg(test)] mod name;` declarations (candidate paths).
    external_test_files: Vec<String>,
    /// The file carries `#![cfg(test)]`.
    test_only: bool,
}

impl SourceFile {
    fn load(path: &str) -> SourceFile {
        let src = read(path);
        let masked = Code::new(mask_literals_and_comments(&src));
        let modules = cfg_test_modules(&masked)
            .unwrap_or_else(|e| panic!("architecture checker cannot read {path}: {e}"));
        let raw_lines: Vec<String> = src.split('\n').map(str::to_owned).collect();
        let mut test_line = vec![false; raw_lines.len()];
        let mut external_test_files = Vec::new();
        for m in &modules {
            test_line[m.first_line - 1..m.last_line].fill(true);
            if !m.inline {
                let dir = module_dir(path);
                external_test_files.push(format!("{dir}/{}.rs", m.name));
                external_test_files.push(format!("{dir}/{}/", m.name));
            }
        }
        // A trailing newline does not start a line.
        if src.ends_with('\n') {
            test_line.pop();
        }
        let raw_lines = raw_lines[..test_line.len()].to_vec();
        let code = masked.without_lines(&test_line);
        let test_only = contains_at_any(&masked.chars, "#![cfg(test)]");
        SourceFile {
            path: path.to_owned(),
            raw_lines,
            test_line,
            code,
            external_test_files,
            test_only,
        }
    }
}

/// The folder that holds the submodule files of the module in `path`.
fn module_dir(path: &str) -> String {
    let (dir, file) = path.rsplit_once('/').unwrap_or((".", path));
    match file {
        "lib.rs" | "main.rs" | "mod.rs" => dir.to_owned(),
        _ => format!("{dir}/{}", file.trim_end_matches(".rs")),
    }
}

/// The non-test source files under `rel_dir`: files of `#[cfg(test)] mod x;`
/// and `#![cfg(test)]` files left out.
fn load_sources(rel_dir: &str) -> Vec<SourceFile> {
    let files: Vec<SourceFile> = rust_files(rel_dir)
        .iter()
        .map(|p| SourceFile::load(p))
        .collect();
    let excluded: Vec<String> = files
        .iter()
        .flat_map(|f| f.external_test_files.iter().cloned())
        .collect();
    files
        .into_iter()
        .filter(|f| !f.test_only)
        .filter(|f| {
            !excluded.iter().any(|x| {
                if x.ends_with('/') {
                    f.path.starts_with(x)
                } else {
                    &f.path == x
                }
            })
        })
        .collect()
}

fn length_checked_sources() -> Vec<SourceFile> {
    LENGTH_CHECKED_DIRS
        .iter()
        .flat_map(|d| load_sources(d))
        .filter(|f| !GENERATED_FILES.contains(&f.path.as_str()))
        .collect()
}

fn excerpt(line: &str) -> String {
    let t = line.trim();
    if t.chars().count() > 100 {
        format!("{}…", t.chars().take(100).collect::<String>())
    } else {
        t.to_owned()
    }
}

// ---------------------------------------------------------------------------
// Cargo.toml.

/// The lines of a manifest that make `krate` a normal dependency:
/// `[dependencies]` and `[target.….dependencies]` entries (also renamed
/// ones, `x = { package = "krate", … }`) and `[dependencies.krate]` tables.
/// `[dev-dependencies]` and `[build-dependencies]` do not count.
fn normal_dependency_entries(toml: &str, krate: &str) -> Vec<(usize, String)> {
    fn is_normal_deps(table: &str) -> bool {
        table == "dependencies"
            || (table.starts_with("target.") && table.ends_with(".dependencies"))
    }
    let unquote = |s: &str| s.trim().trim_matches('"').trim_matches('\'').to_owned();
    let mut out = Vec::new();
    let mut in_deps = false;
    for (k, line) in toml.lines().enumerate() {
        let t = line.trim();
        if t.starts_with('#') || t.is_empty() {
            continue;
        }
        if t.starts_with('[') {
            let table = t
                .trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim();
            in_deps = is_normal_deps(table);
            if let Some((parent, name)) = table.rsplit_once('.') {
                if is_normal_deps(parent) && unquote(name) == krate {
                    out.push((k + 1, t.to_owned()));
                }
            }
            continue;
        }
        if !in_deps {
            continue;
        }
        let key = t.split('=').next().map(unquote).unwrap_or_default();
        let compact: String = t.chars().filter(|c| !c.is_whitespace()).collect();
        if key == krate || compact.contains(&format!("package=\"{krate}\"")) {
            out.push((k + 1, t.to_owned()));
        }
    }
    out
}

mod architecture_scan;
use architecture_scan::*;

// ---------------------------------------------------------------------------
// The skymodel import graph.

struct ImportGraph {
    modules: BTreeSet<String>,
    /// (from, to) → the mentions that make the edge, as `path:line: text`.
    edges: BTreeMap<(String, String), Vec<String>>,
}

impl ImportGraph {
    fn adjacency(&self) -> BTreeMap<String, BTreeSet<String>> {
        let mut adj: BTreeMap<String, BTreeSet<String>> = self
            .modules
            .iter()
            .map(|m| (m.clone(), BTreeSet::new()))
            .collect();
        for (from, to) in self.edges.keys() {
            adj.entry(from.clone()).or_default().insert(to.clone());
        }
        adj
    }
}

fn skymodel_import_graph() -> ImportGraph {
    let src = "skymodel/src";
    let mut modules = BTreeSet::new();
    for entry in fs::read_dir(workspace_root().join(src)).unwrap() {
        let entry = entry.unwrap();
        let name = entry.file_name().to_string_lossy().into_owned();
        if entry.file_type().unwrap().is_dir() {
            modules.insert(name);
        } else if let Some(stem) = name.strip_suffix(".rs") {
            if stem != "lib" && stem != "main" {
                modules.insert(stem.to_owned());
            }
        }
    }

    let files = load_sources(src);
    let root = files
        .iter()
        .find(|f| f.path == format!("{src}/lib.rs"))
        .expect("skymodel/src/lib.rs");
    let reexports = root_reexports(&root.code, &modules);

    let mut edges: BTreeMap<(String, String), Vec<String>> = BTreeMap::new();
    for file in &files {
        let rel = &file.path[src.len() + 1..];
        let from = rel.split('/').next().unwrap().trim_end_matches(".rs");
        if !modules.contains(from) {
            continue; // lib.rs, the crate root
        }
        for (line, head) in crate_path_heads(&file.code) {
            let (to, via) = if modules.contains(&head) {
                (head.clone(), String::new())
            } else if let Some(m) = reexports.get(&head) {
                (
                    m.clone(),
                    format!(" (crate::{head} is {m}::{head}, re-exported by lib.rs)"),
                )
            } else {
                continue;
            };
            if to != from {
                edges
                    .entry((from.to_owned(), to))
                    .or_default()
                    .push(format!(
                        "{}:{line}: {}{via}",
                        file.path,
                        excerpt(&file.raw_lines[line - 1])
                    ));
            }
        }
    }
    ImportGraph { modules, edges }
}

/// The elementary cycles of a directed graph, each written from its
/// smallest node and back to it (`a -> c -> a`), at most `limit` of them.
fn elementary_cycles(adj: &BTreeMap<String, BTreeSet<String>>, limit: usize) -> Vec<Vec<String>> {
    fn dfs(
        adj: &BTreeMap<String, BTreeSet<String>>,
        start: &str,
        path: &mut Vec<String>,
        out: &mut Vec<Vec<String>>,
        limit: usize,
    ) {
        let last = path.last().unwrap().clone();
        for next in adj.get(&last).into_iter().flatten() {
            if out.len() >= limit {
                return;
            }
            if next == start {
                let mut cycle = path.clone();
                cycle.push(start.to_owned());
                out.push(cycle);
            } else if next.as_str() > start && !path.contains(next) {
                path.push(next.clone());
                dfs(adj, start, path, out, limit);
                path.pop();
            }
        }
    }
    let mut out = Vec::new();
    for start in adj.keys() {
        dfs(adj, start, &mut vec![start.clone()], &mut out, limit);
    }
    out
}

// ---------------------------------------------------------------------------
// Tests of the helpers, so that the checks above cannot pass by misreading.

#[cfg(test)]
fn code(src: &str) -> Code {
    Code::new(mask_literals_and_comments(src))
}

#[test]
fn helper_masking_blanks_comments_strings_and_chars_but_keeps_lines() {
    let src = "let a = \"{ \\\" }\"; // { fn x() {\nlet b = '{'; /* { /* } */ { */ let c = '\\''; let d = '\\u{7b}';\n";
    let masked: String = mask_literals_and_comments(src).into_iter().collect();
    assert_eq!(masked.chars().count(), src.chars().count());
    assert_eq!(masked.lines().count(), 2);
    assert!(!masked.contains('{') && !masked.contains('}'), "{masked}");
    assert!(!masked.contains("fn"), "{masked}");
    assert!(masked.contains("let a =") && masked.contains("let c =") && masked.contains("let d ="));
}

#[test]
fn helper_masking_handles_raw_strings_lifetimes_and_raw_identifiers() {
    let src = r##"fn f<'a>(x: &'a str) -> &'static str { let r#type = 1; let s = r#"a "}" b"#; 'l: loop { break 'l; } br"}" }"##;
    let c = code(src);
    let masked: String = c.chars.iter().collect();
    assert!(
        masked.contains("'a>(x: &'a str) -> &'static str"),
        "{masked}"
    );
    assert!(masked.contains("let r#type = 1;"), "{masked}");
    assert!(masked.contains("'l: loop"), "{masked}");
    assert_eq!(masked.matches('}').count(), 2, "{masked}");
    let open = masked.find('{').unwrap();
    assert_eq!(matching_brace(&c, open), Some(c.chars.len() - 1));
}

#[test]
fn helper_brace_matching_skips_braces_in_strings_chars_and_comments() {
    let src = "fn a() {\n    let s = \"}}}\";\n    let c = '}';\n    // }\n    /* } */\n    if true { x(); }\n}\nfn b() {}\n";
    let c = code(src);
    let spans = functions(&c).unwrap();
    assert_eq!(
        spans,
        vec![
            FnSpan {
                name: "a".into(),
                first_line: 1,
                last_line: 7
            },
            FnSpan {
                name: "b".into(),
                first_line: 8,
                last_line: 8
            },
        ]
    );
    assert_eq!(spans[0].lines(), 7);
    assert!(
        matching_brace(&code("{ \"}\" "), 0).is_none(),
        "an unclosed brace is reported"
    );
}

#[test]
fn helper_functions_skip_bodyless_trait_fns_pointer_types_and_macro_fns() {
    let src = "trait T {\n    fn name(&self) -> &'static str;\n    fn arr(&self, x: [u8; 3]) -> [f32; 4];\n    fn default_body(&self) -> u32 {\n        1\n    }\n}\n\
               fn takes(f: fn(u32) -> u32, g: [u8; 2]) -> Option<u32> {\n    let _ = \"fn fake() {\";\n    Some(f(1))\n}\n\
               macro_rules! m { ($n:ident) => { fn $n() {} }; }\n\
               pub(crate) async unsafe fn r#match() where u8: Copy { }\n";
    let spans = functions(&code(src)).unwrap();
    let names: Vec<(&str, usize, usize)> = spans
        .iter()
        .map(|f| (f.name.as_str(), f.first_line, f.last_line))
        .collect();
    assert_eq!(
        names,
        [("default_body", 4, 6), ("takes", 8, 11), ("match", 13, 13)]
    );
}

#[test]
fn helper_cfg_test_modules_are_found_and_stripped() {
    let src = "fn keep() {\n}\n\n#[cfg(test)]\nmod tests {\n    fn inner() { let s = \"}\"; }\n    mod nested { }\n}\n\
               #[cfg(test)]\n#[allow(dead_code)]\npub(crate) mod more_tests {\n    #[cfg(test)]\n    mod deeper {}\n}\n\
               #[cfg(test)]\nmod external;\n#[cfg(test)]\nfn helper() {\n}\n#[cfg(not(test))]\nmod real {}\n";
    let c = code(src);
    let modules = cfg_test_modules(&c).unwrap();
    assert_eq!(
        modules,
        vec![
            TestModule {
                name: "tests".into(),
                first_line: 4,
                last_line: 8,
                inline: true
            },
            TestModule {
                name: "more_tests".into(),
                first_line: 9,
                last_line: 14,
                inline: true
            },
            TestModule {
                name: "external".into(),
                first_line: 15,
                last_line: 16,
                inline: false
            },
        ]
    );
    let mut drop = vec![false; c.line_starts.len()];
    for m in &modules {
        drop[m.first_line - 1..m.last_line].fill(true);
    }
    let names: Vec<String> = functions(&c.without_lines(&drop))
        .unwrap()
        .into_iter()
        .map(|f| f.name)
        .collect();
    assert_eq!(names, ["keep", "helper"]);
    // A #[cfg(test)] inside a comment or string is no attribute.
    assert!(cfg_test_modules(&code(
        "// #[cfg(test)]\nmod a {}\nconst S: &str = \"#[cfg(test)] mod b {}\";\n"
    ))
    .unwrap()
    .is_empty());
}

#[test]
fn helper_module_dir_locates_external_test_files() {
    assert_eq!(module_dir("skymodel/src/lib.rs"), "skymodel/src");
    assert_eq!(module_dir("skymodel/src/moon.rs"), "skymodel/src/moon");
    assert_eq!(
        module_dir("skymodel/src/atmosphere/mod.rs"),
        "skymodel/src/atmosphere"
    );
}

#[test]
fn helper_crate_paths_and_reexports() {
    let src = "use crate::moon::MoonState;\nuse crate::{\n    spectrum::Bands,\n    units::{Lux, Radians},\n};\n\
               // crate::comment::X\nlet s = \"crate::string\";\nlet x: &crate::Scene = y; let z = $crate::m!();\nnotcrate::no;\n";
    let heads = crate_path_heads(&code(src));
    let heads: Vec<(usize, &str)> = heads.iter().map(|(l, h)| (*l, h.as_str())).collect();
    assert_eq!(
        heads,
        [
            (1, "moon"),
            (3, "spectrum"),
            (4, "units"),
            (8, "Scene"),
            (8, "m")
        ]
    );

    let modules: BTreeSet<String> = ["scene", "state", "camera"].map(String::from).into();
    let root = "pub mod scene;\npub use scene::{Effect, Scene as TheScene};\npub use state::SkyState;\nuse crate::camera::{exposure::Exposure};\npub use other::Thing;\n";
    let map = root_reexports(&code(root), &modules);
    let pairs: Vec<(&str, &str)> = map.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    assert_eq!(
        pairs,
        [
            ("Effect", "scene"),
            ("Exposure", "camera"),
            ("SkyState", "state"),
            ("TheScene", "scene")
        ]
    );
}

#[test]
fn helper_cycle_detection() {
    let graph = |edges: &[(&str, &str)]| {
        let mut adj: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (a, b) in edges {
            adj.entry(a.to_string()).or_default().insert(b.to_string());
            adj.entry(b.to_string()).or_default();
        }
        adj
    };
    let none = elementary_cycles(&graph(&[("a", "b"), ("b", "c"), ("a", "c")]), 100);
    assert!(none.is_empty());
    let cycles = elementary_cycles(
        &graph(&[
            ("state", "moon"),
            ("moon", "state"),
            ("b", "c"),
            ("c", "d"),
            ("d", "b"),
        ]),
        100,
    );
    let shown: Vec<String> = cycles.iter().map(|c| c.join(" -> ")).collect();
    assert_eq!(shown, ["b -> c -> d -> b", "moon -> state -> moon"]);
}

#[test]
fn helper_manifest_dependencies() {
    let toml = "[package]\nname = \"himmel-cpu\"\n\n[dependencies]\nglam = \"1\"\nhimmel-cpu = { path = \"../backend-cpu\" }\ncpu = { package = \"himmel-cpu\", path = \"x\" }\n\n\
                [dev-dependencies]\nhimmel-cpu = { path = \"../backend-cpu\" }\n\n[target.'cfg(unix)'.dependencies]\n\"himmel-cpu\" = \"1\"\n\n[dependencies.himmel-cpu]\npath = \"x\"\n";
    let lines: Vec<usize> = normal_dependency_entries(toml, "himmel-cpu")
        .into_iter()
        .map(|(l, _)| l)
        .collect();
    assert_eq!(lines, [6, 7, 13, 15]);
    assert!(
        normal_dependency_entries("[dev-dependencies]\nhimmel-cpu = \"1\"\n", "himmel-cpu")
            .is_empty()
    );
}
