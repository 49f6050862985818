//! The shape of the code, checked: the import graph of `src/` has no cycle,
//! and every top-level module uses only what ARCHITECTURE.md's code map lets
//! it use.
//!
//! The graph has one node per module file (`src/kernel/cell.rs` is
//! `crate::kernel::cell`; the binary's modules hang under `main`). There is
//! an edge `a -> b` when code of `a` names an item of `b`: through a `use`,
//! a path in code (`crate::`, `super::`, `self::`, `tmc::` in the binary, a
//! child module, or a name a `use` brought in), or such a path inside a
//! macro call. Re-exports are followed to the module that defines the item,
//! so `crate::Error` is an edge to `crate::error`. A facade's `pub use` of an
//! item of its own descendants is its table of contents, not a dependency,
//! unless its own code uses the item. Test code (`#[cfg(test)]`) and doc
//! comments are left out: tests may reach anywhere, and a doc link is text.
//!
//! `TMC_IMPORT_GRAPH=1 cargo test --test architecture -- --nocapture`
//! prints the graph (file level and top-level module level).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use syn::visit::Visit;

/// A module path from a crate root: `["crate", "kernel", "cell"]` for the
/// library, `["main", "cli", "batch"]` for the binary.
type ModPath = Vec<String>;

/// What one module file says about the names it uses.
#[derive(Default)]
struct Module {
    file: PathBuf,
    /// Child modules declared with `mod name;`.
    children: BTreeSet<String>,
    /// Names a `use` brings into scope: name -> absolute path.
    aliases: BTreeMap<String, ModPath>,
    /// Names a `pub use` re-exports: name -> absolute path.
    exports: BTreeMap<String, ModPath>,
    /// Absolute paths of `use` declarations: (path, whether `pub`).
    uses: Vec<(ModPath, bool)>,
    /// Paths met in code, as written (resolved once every module is known).
    code_paths: Vec<Vec<String>>,
}

/// Every module of the library and the binary, by path.
struct Crate {
    modules: BTreeMap<ModPath, Module>,
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Whether `attrs` hold `#[cfg(test)]`.
fn is_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg")
            && a.meta
                .require_list()
                .is_ok_and(|l| l.tokens.to_string().trim() == "test")
    })
}

fn item_attrs(item: &syn::Item) -> &[syn::Attribute] {
    use syn::Item::*;
    match item {
        Const(i) => &i.attrs,
        Enum(i) => &i.attrs,
        ExternCrate(i) => &i.attrs,
        Fn(i) => &i.attrs,
        ForeignMod(i) => &i.attrs,
        Impl(i) => &i.attrs,
        Macro(i) => &i.attrs,
        Mod(i) => &i.attrs,
        Static(i) => &i.attrs,
        Struct(i) => &i.attrs,
        Trait(i) => &i.attrs,
        TraitAlias(i) => &i.attrs,
        Type(i) => &i.attrs,
        Union(i) => &i.attrs,
        Use(i) => &i.attrs,
        _ => &[],
    }
}

fn impl_item_attrs(item: &syn::ImplItem) -> &[syn::Attribute] {
    match item {
        syn::ImplItem::Const(i) => &i.attrs,
        syn::ImplItem::Fn(i) => &i.attrs,
        syn::ImplItem::Type(i) => &i.attrs,
        syn::ImplItem::Macro(i) => &i.attrs,
        _ => &[],
    }
}

/// Flattens a use tree into (path, bound name; `None` for a glob).
fn flatten(
    tree: &syn::UseTree,
    prefix: &mut Vec<String>,
    out: &mut Vec<(Vec<String>, Option<String>)>,
) {
    match tree {
        syn::UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            flatten(&p.tree, prefix, out);
            prefix.pop();
        }
        syn::UseTree::Name(n) => {
            let name = n.ident.to_string();
            if name == "self" {
                let bound = prefix.last().cloned();
                out.push((prefix.clone(), bound));
            } else {
                let mut p = prefix.clone();
                p.push(name.clone());
                out.push((p, Some(name)));
            }
        }
        syn::UseTree::Rename(r) => {
            let mut p = prefix.clone();
            if r.ident != "self" {
                p.push(r.ident.to_string());
            }
            out.push((p, Some(r.rename.to_string())));
        }
        syn::UseTree::Glob(_) => out.push((prefix.clone(), None)),
        syn::UseTree::Group(g) => {
            for t in &g.items {
                flatten(t, prefix, out);
            }
        }
    }
}

/// Collects the paths in code and the `use` declarations nested in it,
/// leaving test code out.
struct Collector<'m> {
    module: &'m mut Module,
    /// Uses met inside function bodies, flattened, with their visibility.
    nested_uses: Vec<(Vec<String>, Option<String>, bool)>,
}

impl<'ast> Visit<'ast> for Collector<'_> {
    fn visit_item(&mut self, item: &'ast syn::Item) {
        if !is_test(item_attrs(item)) {
            syn::visit::visit_item(self, item);
        }
    }

    fn visit_impl_item(&mut self, item: &'ast syn::ImplItem) {
        if !is_test(impl_item_attrs(item)) {
            syn::visit::visit_impl_item(self, item);
        }
    }

    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        let mut out = Vec::new();
        flatten(&u.tree, &mut Vec::new(), &mut out);
        let public = !matches!(u.vis, syn::Visibility::Inherited);
        for (path, name) in out {
            self.nested_uses.push((path, name, public));
        }
    }

    fn visit_path(&mut self, path: &'ast syn::Path) {
        let segments: Vec<String> = path.segments.iter().map(|s| s.ident.to_string()).collect();
        self.module.code_paths.push(segments);
        syn::visit::visit_path(self, path);
    }

    fn visit_visibility(&mut self, _: &'ast syn::Visibility) {
        // `pub(crate)` names a scope, not an item.
    }

    fn visit_macro(&mut self, mac: &'ast syn::Macro) {
        // Macro arguments are tokens, not syntax: find `a::b::c` runs in
        // them (a lone identifier there is most often a local variable).
        let mut runs = Vec::new();
        scan_tokens(mac.tokens.clone(), &mut runs);
        self.module
            .code_paths
            .extend(runs.into_iter().filter(|r| r.len() > 1));
        syn::visit::visit_macro(self, mac);
    }
}

/// Appends every `ident (:: ident)*` run of `tokens` (at any depth) to `out`.
fn scan_tokens(tokens: proc_macro2::TokenStream, out: &mut Vec<Vec<String>>) {
    use proc_macro2::TokenTree;
    let trees: Vec<TokenTree> = tokens.into_iter().collect();
    let mut i = 0;
    while i < trees.len() {
        match &trees[i] {
            TokenTree::Group(g) => {
                scan_tokens(g.stream(), out);
                i += 1;
            }
            TokenTree::Ident(first) => {
                let mut path = vec![first.to_string()];
                let mut j = i + 1;
                while let (
                    Some(TokenTree::Punct(a)),
                    Some(TokenTree::Punct(b)),
                    Some(TokenTree::Ident(next)),
                ) = (trees.get(j), trees.get(j + 1), trees.get(j + 2))
                {
                    if a.as_char() != ':' || b.as_char() != ':' {
                        break;
                    }
                    path.push(next.to_string());
                    j += 3;
                }
                out.push(path);
                i = j;
            }
            _ => i += 1,
        }
    }
}

impl Crate {
    fn load() -> Crate {
        let mut krate = Crate {
            modules: BTreeMap::new(),
        };
        krate.load_module(vec!["crate".into()], &src().join("lib.rs"), true);
        krate.load_module(vec!["main".into()], &src().join("main.rs"), true);
        krate
    }

    /// Reads the module at `file` and, recursively, its child modules.
    /// `owns_dir`: the file is `lib.rs`, `main.rs` or `mod.rs`, whose
    /// children live beside it (else in a folder named after the file).
    fn load_module(&mut self, path: ModPath, file: &Path, owns_dir: bool) {
        let text =
            std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let ast = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let mut module = Module {
            file: file.to_path_buf(),
            ..Module::default()
        };
        let dir = if owns_dir {
            file.parent().unwrap().to_path_buf()
        } else {
            file.with_extension("")
        };
        let mut children = Vec::new();
        let mut uses = Vec::new();
        {
            let mut collector = Collector {
                module: &mut module,
                nested_uses: Vec::new(),
            };
            for item in &ast.items {
                if is_test(item_attrs(item)) {
                    continue;
                }
                match item {
                    syn::Item::Mod(m) if m.content.is_none() => {
                        collector.module.children.insert(m.ident.to_string());
                        children.push(m.ident.to_string());
                    }
                    _ => collector.visit_item(item),
                }
            }
            uses.append(&mut collector.nested_uses);
        }
        let is_bin = path[0] == "main";
        // Child modules first known, so that `use child::x` resolves.
        for (raw, name, public) in &uses {
            let Some(abs) = absolute(&path, raw, &module.children, &BTreeMap::new(), is_bin) else {
                continue;
            };
            if let Some(name) = name {
                module.aliases.insert(name.clone(), abs.clone());
                if *public {
                    module.exports.insert(name.clone(), abs.clone());
                }
            }
            module.uses.push((abs, *public));
        }
        self.modules.insert(path.clone(), module);
        for child in children {
            let mut child_path = path.clone();
            child_path.push(child.clone());
            let flat = dir.join(format!("{child}.rs"));
            if flat.exists() {
                self.load_module(child_path, &flat, false);
            } else {
                self.load_module(child_path, &dir.join(&child).join("mod.rs"), true);
            }
        }
    }

    /// The module that defines the item at `abs`, re-exports followed.
    fn resolve(&self, abs: &[String]) -> Option<ModPath> {
        let mut abs = abs.to_vec();
        for _ in 0..32 {
            let len = (1..=abs.len())
                .rev()
                .find(|&n| self.modules.contains_key(&abs[..n]))?;
            let module = &self.modules[&abs[..len]];
            let Some(target) = abs.get(len).and_then(|name| module.exports.get(name)) else {
                return Some(abs[..len].to_vec());
            };
            let mut next = target.clone();
            next.extend_from_slice(&abs[len + 1..]);
            if next == abs {
                return Some(abs[..len].to_vec());
            }
            abs = next;
        }
        panic!("re-exports of {abs:?} go round in a circle")
    }

    /// File-level edges `a -> {b}`.
    fn edges(&self) -> BTreeMap<ModPath, BTreeSet<ModPath>> {
        let mut edges: BTreeMap<ModPath, BTreeSet<ModPath>> = BTreeMap::new();
        for (path, module) in &self.modules {
            let is_bin = path[0] == "main";
            let out = edges.entry(path.clone()).or_default();
            for (abs, public) in &module.uses {
                let Some(target) = self.resolve(abs) else {
                    continue;
                };
                let table_of_contents = *public && target.starts_with(path);
                if !table_of_contents {
                    out.insert(target);
                }
            }
            for raw in &module.code_paths {
                let Some(abs) = absolute(path, raw, &module.children, &module.aliases, is_bin)
                else {
                    continue;
                };
                if let Some(target) = self.resolve(&abs) {
                    out.insert(target);
                }
            }
            out.remove(path);
        }
        edges
    }
}

/// The absolute path of `raw` as written in module `at`, or `None` when it
/// names nothing of this crate (std, another crate, a local).
fn absolute(
    at: &ModPath,
    raw: &[String],
    children: &BTreeSet<String>,
    aliases: &BTreeMap<String, ModPath>,
    is_bin: bool,
) -> Option<ModPath> {
    let first = raw.first()?;
    let (mut base, rest): (ModPath, &[String]) = match first.as_str() {
        "crate" => (
            vec![if is_bin { "main" } else { "crate" }.into()],
            &raw[1..],
        ),
        "tmc" if is_bin => (vec!["crate".into()], &raw[1..]),
        "self" => (at.clone(), &raw[1..]),
        "super" => {
            let mut base = at.clone();
            let mut rest = raw;
            while rest.first().is_some_and(|s| s == "super") {
                base.pop();
                rest = &rest[1..];
            }
            (base, rest)
        }
        name if children.contains(name) => (at.clone(), raw),
        name => match aliases.get(name) {
            Some(target) => (target.clone(), &raw[1..]),
            None => return None,
        },
    };
    base.extend(rest.iter().cloned());
    Some(base)
}

/// The top-level module a module belongs to: `kernel` for
/// `crate::kernel::cell`, `cli` for `main::cli::batch`; the roots are
/// `lib` and `main`.
fn unit(path: &ModPath) -> String {
    match (path[0].as_str(), path.get(1)) {
        ("crate", Some(top)) => top.clone(),
        ("crate", None) => "lib".into(),
        (_, Some(top)) => top.clone(),
        (_, None) => "main".into(),
    }
}

fn show(path: &ModPath) -> String {
    path.join("::")
}

/// The strongly connected components of more than one module (Tarjan).
fn cycles(edges: &BTreeMap<ModPath, BTreeSet<ModPath>>) -> Vec<Vec<ModPath>> {
    struct State<'a> {
        edges: &'a BTreeMap<ModPath, BTreeSet<ModPath>>,
        index: BTreeMap<&'a ModPath, usize>,
        low: BTreeMap<&'a ModPath, usize>,
        stack: Vec<&'a ModPath>,
        on_stack: BTreeSet<&'a ModPath>,
        found: Vec<Vec<ModPath>>,
    }
    fn connect<'a>(s: &mut State<'a>, v: &'a ModPath) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        let edges = s.edges;
        for w in edges.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                connect(s, w);
                let low = s.low[w].min(s.low[v]);
                s.low.insert(v, low);
            } else if s.on_stack.contains(w) {
                let low = s.index[w].min(s.low[v]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            loop {
                let w = s.stack.pop().unwrap();
                s.on_stack.remove(w);
                component.push(w.clone());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort();
                s.found.push(component);
            }
        }
    }
    let mut s = State {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for v in edges.keys() {
        if !s.index.contains_key(v) {
            connect(&mut s, v);
        }
    }
    s.found
}

/// The code map of ARCHITECTURE.md: top-level module -> the top-level
/// modules it may use. Read from the table whose header starts with
/// `| module | owns | may use`; a module cell is a backticked name (a
/// trailing `/` or `.rs` is dropped), the last cell lists backticked names.
fn code_map() -> BTreeMap<String, BTreeSet<String>> {
    let doc = Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md");
    let text = std::fs::read_to_string(&doc).expect("ARCHITECTURE.md");
    let names = |cell: &str| -> Vec<String> {
        cell.split('`')
            .skip(1)
            .step_by(2)
            .map(|n| n.trim_end_matches('/').trim_end_matches(".rs").to_string())
            .collect()
    };
    let mut map = BTreeMap::new();
    let mut in_table = false;
    for line in text.lines() {
        let cells: Vec<&str> = line
            .trim()
            .trim_matches('|')
            .split('|')
            .map(str::trim)
            .collect();
        if line.trim_start().starts_with("| module | owns | may use") {
            in_table = true;
            continue;
        }
        if !in_table {
            continue;
        }
        if !line.trim_start().starts_with('|') {
            break;
        }
        if cells
            .iter()
            .all(|c| c.chars().all(|ch| ch == '-' || ch == ':'))
        {
            continue;
        }
        let module = names(cells[0]);
        assert_eq!(
            module.len(),
            1,
            "ARCHITECTURE.md code map row names one module: {line}"
        );
        let allowed: BTreeSet<String> = names(cells.last().unwrap()).into_iter().collect();
        map.insert(module[0].clone(), allowed);
    }
    assert!(
        !map.is_empty(),
        "ARCHITECTURE.md has no '| module | owns | may use |' table"
    );
    map
}

fn print_graph(krate: &Crate, edges: &BTreeMap<ModPath, BTreeSet<ModPath>>) {
    if std::env::var_os("TMC_IMPORT_GRAPH").is_none() {
        return;
    }
    println!("# modules: {}", krate.modules.len());
    let mut units: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (a, targets) in edges {
        let list: Vec<String> = targets.iter().map(show).collect();
        println!("{} -> {}", show(a), list.join(", "));
        for b in targets {
            if unit(a) != unit(b) {
                units.entry(unit(a)).or_default().insert(unit(b));
            }
        }
    }
    println!("# top-level modules");
    for (a, targets) in units {
        println!(
            "{a} -> {}",
            targets.into_iter().collect::<Vec<_>>().join(", ")
        );
    }
}

#[test]
fn the_import_graph_has_no_cycle() {
    let krate = Crate::load();
    let edges = krate.edges();
    print_graph(&krate, &edges);
    assert!(
        krate.modules.len() > 50,
        "found only {} modules",
        krate.modules.len()
    );
    let found = cycles(&edges);
    let text: Vec<String> = found
        .iter()
        .map(|c| {
            let names: Vec<String> = c.iter().map(show).collect();
            let files: Vec<String> = c
                .iter()
                .map(|m| {
                    krate.modules[m]
                        .file
                        .strip_prefix(src())
                        .unwrap()
                        .display()
                        .to_string()
                })
                .collect();
            format!("  {{{}}} ({})", names.join(", "), files.join(", "))
        })
        .collect();
    assert!(
        found.is_empty(),
        "modules that use each other in a circle:\n{}",
        text.join("\n")
    );
}

#[test]
fn top_level_modules_use_only_what_the_code_map_allows() {
    let krate = Crate::load();
    let edges = krate.edges();
    let map = code_map();
    let mut problems = Vec::new();
    let units: BTreeSet<String> = krate.modules.keys().map(unit).collect();
    for u in &units {
        if !map.contains_key(u) && u != "lib" && u != "main" {
            problems.push(format!("`{u}` has no row in ARCHITECTURE.md's code map"));
        }
    }
    for (u, allowed) in &map {
        if !units.contains(u) {
            problems.push(format!(
                "ARCHITECTURE.md's code map names `{u}`, which src/ does not have"
            ));
        }
        for a in allowed {
            if !units.contains(a) {
                problems.push(format!(
                    "ARCHITECTURE.md lets `{u}` use `{a}`, which src/ does not have"
                ));
            }
        }
    }
    for (a, targets) in &edges {
        let (ua, allowed) = (unit(a), map.get(&unit(a)));
        for b in targets {
            let ub = unit(b);
            if ua == ub || ua == "lib" || ua == "main" {
                continue;
            }
            if !allowed.is_some_and(|s| s.contains(&ub)) {
                problems.push(format!(
                    "{} uses {}, but ARCHITECTURE.md does not let `{ua}` use `{ub}`",
                    show(a),
                    show(b)
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The checker itself: a planted cycle and a planted layer breach are found.
#[test]
fn the_checker_finds_a_planted_cycle() {
    let p = |s: &str| -> ModPath { s.split("::").map(String::from).collect() };
    let mut edges: BTreeMap<ModPath, BTreeSet<ModPath>> = BTreeMap::new();
    edges
        .entry(p("crate::a"))
        .or_default()
        .insert(p("crate::b"));
    edges
        .entry(p("crate::b"))
        .or_default()
        .insert(p("crate::c"));
    edges
        .entry(p("crate::c"))
        .or_default()
        .insert(p("crate::d"));
    assert!(cycles(&edges).is_empty());
    edges
        .entry(p("crate::c"))
        .or_default()
        .insert(p("crate::a"));
    assert_eq!(
        cycles(&edges),
        vec![vec![p("crate::a"), p("crate::b"), p("crate::c")]]
    );
    // Resolution through a re-export and `super`.
    let children = BTreeSet::from(["x".to_string()]);
    let aliases = BTreeMap::from([("E".to_string(), p("crate::error::E"))]);
    let at = p("crate::kernel::cell");
    assert_eq!(
        absolute(
            &at,
            &["super".into(), "cube".into()],
            &children,
            &aliases,
            false
        ),
        Some(p("crate::kernel::cube"))
    );
    assert_eq!(
        absolute(&at, &["E".into(), "new".into()], &children, &aliases, false),
        Some(p("crate::error::E::new"))
    );
    assert_eq!(
        absolute(&at, &["tmc".into(), "x".into()], &children, &aliases, true),
        Some(p("crate::x"))
    );
    assert_eq!(
        absolute(
            &at,
            &["std".into(), "io".into()],
            &children,
            &aliases,
            false
        ),
        None
    );
}

/// Every file below `root`, leaving out the folders whose name `skip` picks
/// (every file in them, even a stray one no module declares).
fn files_under(root: &Path, skip: impl Fn(&str) -> bool) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if !path.is_dir() {
                files.push(path);
            } else if !skip(&path.file_name().unwrap().to_string_lossy()) {
                stack.push(path);
            }
        }
    }
    files
}

/// No file of the repository names a path that exists on one machine only
/// (a home directory, a build machine's work tree): the scripts, docs and
/// tests must work from any checkout.
#[test]
fn no_file_names_a_path_of_one_machine() {
    // Built from pieces, so that this file does not match itself.
    let patterns: Vec<String> = [
        ["/wo", "rk/"],
        ["/ro", "ot/"],
        ["/ho", "me/"],
        ["/Us", "ers/"],
    ]
    .iter()
    .map(|p| p.concat())
    .collect();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    // Build output, version control and local virtual environments are
    // not the repository's (but `.ci` is).
    let skip = |name: &str| {
        name != ".ci" && (name == "target" || name.starts_with('.') || name == "__pycache__")
    };
    let mut found = Vec::new();
    for path in files_under(root, skip) {
        // A linked worktree's `.git` is a file naming where the repository is.
        if path
            .file_name()
            .is_some_and(|n| n == "Cargo.lock" || n == ".git")
        {
            continue;
        }
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue; // not UTF-8 text: volumes, images
        };
        for (n, line) in text.lines().enumerate() {
            if patterns.iter().any(|p| line.contains(p.as_str())) {
                let rel = path.strip_prefix(root).unwrap().display().to_string();
                found.push(format!("{rel}:{}: {}", n + 1, line.trim()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "machine-specific paths:\n{}",
        found.join("\n")
    );
}

/// Finds `unsafe` blocks, functions, impls and traits, test code included.
#[derive(Default)]
struct UnsafeFinder {
    found: usize,
}

impl<'ast> Visit<'ast> for UnsafeFinder {
    fn visit_expr_unsafe(&mut self, e: &'ast syn::ExprUnsafe) {
        self.found += 1;
        syn::visit::visit_expr_unsafe(self, e);
    }

    fn visit_signature(&mut self, sig: &'ast syn::Signature) {
        self.found += usize::from(sig.unsafety.is_some());
        syn::visit::visit_signature(self, sig);
    }

    fn visit_item_impl(&mut self, i: &'ast syn::ItemImpl) {
        self.found += usize::from(i.unsafety.is_some());
        syn::visit::visit_item_impl(self, i);
    }

    fn visit_item_trait(&mut self, i: &'ast syn::ItemTrait) {
        self.found += usize::from(i.unsafety.is_some());
        syn::visit::visit_item_trait(self, i);
    }
}

/// `unsafe` only where memory mapping and signal handling need it (the
/// invariant in ARCHITECTURE.md, which names these files; change both
/// together). Each block's `// SAFETY:` comment is required by clippy's
/// `undocumented_unsafe_blocks` (denied in lib.rs and main.rs).
#[test]
fn unsafe_code_is_only_where_mapping_and_signals_need_it() {
    const ALLOWED: [&str; 3] = [
        "volume/mapped.rs",
        "cli/signals.rs",
        "files/fatal_cleanup.rs",
    ];
    check_unsafe_only_in(&src(), &ALLOWED);
    // The Python package: only where a numpy array's memory is borrowed.
    let python = Path::new(env!("CARGO_MANIFEST_DIR")).join("python/src");
    check_unsafe_only_in(&python, &["array.rs"]);
}

/// Fails unless the `.rs` files under `root` with `unsafe` code are
/// exactly `allowed` (paths relative to `root`); the first must have some,
/// so that a scan that finds nothing fails too.
fn check_unsafe_only_in(root: &Path, allowed: &[&str]) {
    let files = files_under(root, |_| false);
    let mut with_unsafe = BTreeSet::new();
    for file in files
        .iter()
        .filter(|f| f.extension().is_some_and(|e| e == "rs"))
    {
        let text = std::fs::read_to_string(file).unwrap();
        let ast = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let mut finder = UnsafeFinder::default();
        finder.visit_file(&ast);
        if finder.found > 0 {
            let rel = file.strip_prefix(root).unwrap().display().to_string();
            with_unsafe.insert(rel);
        }
    }
    assert!(
        with_unsafe.contains(allowed[0]),
        "the scan found no unsafe in {}: {with_unsafe:?}",
        allowed[0]
    );
    let extra: Vec<&String> = with_unsafe
        .iter()
        .filter(|f| !allowed.contains(&f.as_str()))
        .collect();
    assert!(
        extra.is_empty(),
        "unsafe code outside {allowed:?}: {extra:?}"
    );
}
