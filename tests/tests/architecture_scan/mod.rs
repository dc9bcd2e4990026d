//! The Rust-source scanner of `architecture.rs`: comments, strings and
//! char literals blanked out (line structure kept), brace matching,
//! `#[cfg(test)]` modules, function spans and `crate::` paths.
#![allow(dead_code)]

use std::collections::{BTreeMap, BTreeSet};

// ---------------------------------------------------------------------------
// Lexing: blanking comments and literals.

pub fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// `src` with comments, string literals and char literals replaced by spaces
/// (newlines kept, so lines and columns stay where they were): what remains
/// is code, where every `{`, `}`, `fn` and `crate::` is a real one.
pub fn mask_literals_and_comments(src: &str) -> Vec<char> {
    let c: Vec<char> = src.chars().collect();
    let n = c.len();
    let at = |k: usize| c.get(k).copied().unwrap_or('\0');
    let mut out = c.clone();
    let mut i = 0;
    while i < n {
        let prev = if i > 0 { c[i - 1] } else { '\0' };
        let end = match c[i] {
            '/' if at(i + 1) == '/' => Some((i..n).find(|&j| c[j] == '\n').unwrap_or(n)),
            '/' if at(i + 1) == '*' => {
                let (mut j, mut depth) = (i + 2, 1);
                while j < n && depth > 0 {
                    if c[j] == '/' && at(j + 1) == '*' {
                        depth += 1;
                        j += 2;
                    } else if c[j] == '*' && at(j + 1) == '/' {
                        depth -= 1;
                        j += 2;
                    } else {
                        j += 1;
                    }
                }
                Some(j)
            }
            '"' => {
                let mut j = i + 1;
                while j < n && c[j] != '"' {
                    j += if c[j] == '\\' { 2 } else { 1 };
                }
                Some((j + 1).min(n))
            }
            // r"…", r#"…"#, br"…" (but not the raw identifier r#type).
            'r' if !is_ident(prev) || (prev == 'b' && (i < 2 || !is_ident(c[i - 2]))) => {
                let hashes = (i + 1..n).take_while(|&j| c[j] == '#').count();
                if at(i + 1 + hashes) == '"' {
                    let mut j = i + 2 + hashes;
                    loop {
                        if j >= n {
                            break Some(n);
                        }
                        if c[j] == '"' && (1..=hashes).all(|h| at(j + h) == '#') {
                            break Some(j + 1 + hashes);
                        }
                        j += 1;
                    }
                } else {
                    None
                }
            }
            '\'' => {
                if at(i + 1) == '\\' {
                    // '\n', '\'', '\\', '\u{7b}': up to the next quote after
                    // the escaped character.
                    let close = (i + 3..n)
                        .take_while(|&j| c[j] != '\n')
                        .find(|&j| c[j] == '\'');
                    close.map(|j| j + 1)
                } else if at(i + 2) == '\'' && at(i + 1) != '\n' {
                    Some(i + 3)
                } else {
                    None // a lifetime or a label
                }
            }
            _ => None,
        };
        match end {
            Some(j) => {
                for ch in &mut out[i..j] {
                    if *ch != '\n' {
                        *ch = ' ';
                    }
                }
                i = j;
            }
            None => i += 1,
        }
    }
    out
}

/// Masked code with its line index.
pub struct Code {
    pub chars: Vec<char>,
    /// Index of the first character of each line.
    pub line_starts: Vec<usize>,
}

impl Code {
    pub fn new(chars: Vec<char>) -> Code {
        let mut line_starts = vec![0];
        line_starts.extend(
            chars
                .iter()
                .enumerate()
                .filter(|(_, c)| **c == '\n')
                .map(|(k, _)| k + 1),
        );
        Code { chars, line_starts }
    }

    /// The 1-based line of character `idx`.
    pub fn line(&self, idx: usize) -> usize {
        self.line_starts.partition_point(|&s| s <= idx)
    }

    pub fn at(&self, k: usize) -> char {
        self.chars.get(k).copied().unwrap_or('\0')
    }

    pub fn skip_ws(&self, mut k: usize) -> usize {
        while self.at(k).is_whitespace() {
            k += 1;
        }
        k
    }

    /// The identifier starting at `k` (a raw `r#` prefix dropped), if any.
    pub fn ident_at(&self, k: usize) -> Option<(String, usize)> {
        let k = if self.at(k) == 'r' && self.at(k + 1) == '#' {
            k + 2
        } else {
            k
        };
        if !(self.at(k).is_alphabetic() || self.at(k) == '_') {
            return None;
        }
        let end = (k..self.chars.len())
            .find(|&j| !is_ident(self.chars[j]))
            .unwrap_or(self.chars.len());
        Some((self.chars[k..end].iter().collect(), end))
    }

    /// Whether the word `w` stands at `k` (not inside a longer identifier).
    pub fn word_at(&self, k: usize, w: &str) -> bool {
        let len = w.chars().count();
        starts_with_at(&self.chars, k, w)
            && (k == 0 || !is_ident(self.chars[k - 1]))
            && !is_ident(self.at(k + len))
    }

    /// This code with the lines flagged in `drop` blanked (newlines kept).
    pub fn without_lines(&self, drop: &[bool]) -> Code {
        let mut chars = self.chars.clone();
        for (k, ch) in chars.iter_mut().enumerate() {
            if *ch != '\n' && drop.get(self.line(k) - 1).copied().unwrap_or(false) {
                *ch = ' ';
            }
        }
        Code::new(chars)
    }
}

pub fn starts_with_at(chars: &[char], k: usize, s: &str) -> bool {
    (k..).zip(s.chars()).all(|(j, c)| chars.get(j) == Some(&c))
}

pub fn contains_at_any(chars: &[char], s: &str) -> bool {
    (0..chars.len()).any(|k| starts_with_at(chars, k, s))
}

/// The index of the `close` bracket matching the `open` one at `start`, in
/// masked code (so brackets in literals and comments are already gone).
pub fn matching(chars: &[char], start: usize, open: char, close: char) -> Option<usize> {
    let mut depth = 0usize;
    for (k, &c) in chars.iter().enumerate().skip(start) {
        if c == open {
            depth += 1;
        } else if c == close {
            depth = depth.checked_sub(1)?;
            if depth == 0 {
                return Some(k);
            }
        }
    }
    None
}

pub fn matching_brace(code: &Code, open: usize) -> Option<usize> {
    matching(&code.chars, open, '{', '}')
}

// ---------------------------------------------------------------------------
// Items: #[cfg(test)] modules, functions, crate:: paths.

/// A `#[cfg(test)] mod name { … }` (inline) or `#[cfg(test)] mod name;`.
#[derive(Debug, PartialEq)]
pub struct TestModule {
    pub name: String,
    /// The line of the `#[cfg(test)]` attribute.
    pub first_line: usize,
    /// The line of the closing brace (or of the `;`).
    pub last_line: usize,
    pub inline: bool,
}

pub fn cfg_test_modules(code: &Code) -> Result<Vec<TestModule>, String> {
    let mut out: Vec<TestModule> = Vec::new();
    let attr = "#[cfg(test)]";
    for i in (0..code.chars.len()).filter(|&i| starts_with_at(&code.chars, i, attr)) {
        let mut k = code.skip_ws(i + attr.len());
        while code.at(k) == '#' && code.at(k + 1) == '[' {
            let end = matching(&code.chars, k + 1, '[', ']')
                .ok_or_else(|| format!("unclosed attribute at line {}", code.line(k)))?;
            k = code.skip_ws(end + 1);
        }
        if code.word_at(k, "pub") {
            k = code.skip_ws(k + 3);
            if code.at(k) == '(' {
                k = matching(&code.chars, k, '(', ')').map_or(k, |e| e + 1);
                k = code.skip_ws(k);
            }
        }
        if !code.word_at(k, "mod") {
            continue; // #[cfg(test)] on a fn, a use, an impl…: not stripped.
        }
        let Some((name, after)) = code.ident_at(code.skip_ws(k + 3)) else {
            continue;
        };
        let k = code.skip_ws(after);
        let first_line = code.line(i);
        let module = match code.at(k) {
            '{' => {
                let close = matching_brace(code, k).ok_or_else(|| {
                    format!("no closing brace for #[cfg(test)] mod {name} (line {first_line})")
                })?;
                TestModule {
                    name,
                    first_line,
                    last_line: code.line(close),
                    inline: true,
                }
            }
            ';' => TestModule {
                name,
                first_line,
                last_line: code.line(k),
                inline: false,
            },
            _ => continue,
        };
        // A test module nested in another one is already covered.
        if !out
            .iter()
            .any(|m| m.first_line <= module.first_line && module.last_line <= m.last_line)
        {
            out.push(module);
        }
    }
    Ok(out)
}

/// A function item with a body.
#[derive(Debug, PartialEq)]
pub struct FnSpan {
    pub name: String,
    /// The line with `fn name`.
    pub first_line: usize,
    /// The line of the brace that closes the body.
    pub last_line: usize,
}

impl FnSpan {
    pub fn lines(&self) -> usize {
        self.last_line - self.first_line + 1
    }
}

/// Every `fn name` item of masked code that has a body, nested ones
/// included; bodyless ones (`fn f();` in traits and `extern` blocks) are
/// skipped, as are `fn(…)` pointer types and `fn $name` in macros.
pub fn functions(code: &Code) -> Result<Vec<FnSpan>, String> {
    let mut out = Vec::new();
    for i in (0..code.chars.len()).filter(|&i| code.word_at(i, "fn")) {
        let Some((name, after)) = code.ident_at(code.skip_ws(i + 2)) else {
            continue;
        };
        let first_line = code.line(i);
        // The body opens at the first `{` outside (…) and […]; a `;` there
        // first means no body.
        let mut depth = 0i32;
        let mut body = None;
        for k in after..code.chars.len() {
            match code.chars[k] {
                '(' | '[' => depth += 1,
                ')' | ']' => depth -= 1,
                '{' if depth == 0 => {
                    body = Some(k);
                    break;
                }
                ';' if depth == 0 => break,
                _ => {}
            }
        }
        let Some(open) = body else { continue };
        let close = matching_brace(code, open)
            .ok_or_else(|| format!("no closing brace for fn {name} (line {first_line})"))?;
        out.push(FnSpan {
            name,
            first_line,
            last_line: code.line(close),
        });
    }
    Ok(out)
}

/// The first segment of every `crate::` path in masked code, with its line:
/// `crate::a::B` gives `a`, `crate::{a::B, c}` gives `a` and `c`.
pub fn crate_path_heads(code: &Code) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for i in 0..code.chars.len() {
        // `$crate` in macros counts too; `word_at` accepts a `$` before.
        if !code.word_at(i, "crate") {
            continue;
        }
        let k = code.skip_ws(i + 5);
        if !(code.at(k) == ':' && code.at(k + 1) == ':') {
            continue;
        }
        let k = code.skip_ws(k + 2);
        if code.at(k) == '{' {
            let Some(close) = matching_brace(code, k) else {
                continue;
            };
            // Top-level items of the group.
            let (mut depth, mut item_start) = (0, k + 1);
            for j in k + 1..=close {
                match code.chars[j] {
                    '{' => depth += 1,
                    '}' if depth > 0 => depth -= 1,
                    ',' | '}' if depth == 0 => {
                        let s = code.skip_ws(item_start);
                        if let Some((head, _)) = code.ident_at(s) {
                            out.push((code.line(s), head));
                        }
                        item_start = j + 1;
                    }
                    _ => {}
                }
            }
        } else if let Some((head, _)) = code.ident_at(k) {
            out.push((code.line(k), head));
        }
    }
    out
}

/// Names that the crate root brings in with `use m::…` (`pub` or not), mapped
/// to their module `m`: `pub use state::{SkyState, SunState as Sun}` maps
/// `SkyState` and `Sun` to `state`. Glob imports are not resolved.
pub fn root_reexports(code: &Code, modules: &BTreeSet<String>) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for i in (0..code.chars.len()).filter(|&i| code.word_at(i, "use")) {
        let Some(end) = (i..code.chars.len()).find(|&j| code.chars[j] == ';') else {
            continue;
        };
        let stmt: String = code.chars[i + 3..end].iter().collect();
        let stmt = stmt.trim();
        let stmt = stmt
            .strip_prefix("crate::")
            .or(stmt.strip_prefix("self::"))
            .unwrap_or(stmt);
        let Some((module, rest)) = stmt.split_once("::") else {
            continue;
        };
        let module = module.trim();
        if !modules.contains(module) {
            continue;
        }
        for item in rest.split([',', '{', '}']) {
            let words: Vec<&str> = item.split_whitespace().collect();
            let name = match words.as_slice() {
                [_, "as", alias] => alias,
                [path] => path.rsplit("::").next().unwrap_or(path),
                _ => continue,
            };
            if !matches!(name, "" | "*" | "self" | "_") {
                out.insert(name.to_string(), module.to_owned());
            }
        }
    }
    out
}
