//! Import cycles: the strongly connected components of a crate's import graph with more than
//! one module (Tarjan's algorithm), each reported with its modules and the imports that close
//! it.

use crate::resolve::Edge;
use crate::tree::Module;

/// One cycle: its modules (indices, in index order) and the edges between them.
#[derive(Debug)]
pub struct Cycle {
    pub modules: Vec<usize>,
    pub edges: Vec<Edge>,
}

/// Every cycle of the graph of `n` modules with `edges`.
pub fn cycles(n: usize, edges: &[Edge]) -> Vec<Cycle> {
    let mut next: Vec<Vec<usize>> = vec![Vec::new(); n];
    for e in edges {
        next[e.from].push(e.to);
    }
    let mut t = Tarjan {
        next: &next,
        index: vec![None; n],
        low: vec![0; n],
        stack: Vec::new(),
        on_stack: vec![false; n],
        counter: 0,
        components: Vec::new(),
    };
    for v in 0..n {
        if t.index[v].is_none() {
            t.visit(v);
        }
    }
    t.components
        .into_iter()
        .filter(|c| c.len() > 1)
        .map(|mut modules| {
            modules.sort_unstable();
            let inside = |m: usize| modules.binary_search(&m).is_ok();
            let edges = edges
                .iter()
                .filter(|e| inside(e.from) && inside(e.to))
                .cloned()
                .collect();
            Cycle { modules, edges }
        })
        .collect()
}

struct Tarjan<'a> {
    next: &'a [Vec<usize>],
    index: Vec<Option<usize>>,
    low: Vec<usize>,
    stack: Vec<usize>,
    on_stack: Vec<bool>,
    counter: usize,
    components: Vec<Vec<usize>>,
}

impl Tarjan<'_> {
    fn visit(&mut self, v: usize) {
        self.index[v] = Some(self.counter);
        self.low[v] = self.counter;
        self.counter += 1;
        self.stack.push(v);
        self.on_stack[v] = true;
        for &w in &self.next[v] {
            match self.index[w] {
                None => {
                    self.visit(w);
                    self.low[v] = self.low[v].min(self.low[w]);
                }
                Some(iw) if self.on_stack[w] => self.low[v] = self.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(self.low[v]) == self.index[v] {
            let mut component = Vec::new();
            loop {
                let w = self.stack.pop().expect("v is on the stack");
                self.on_stack[w] = false;
                component.push(w);
                if w == v {
                    break;
                }
            }
            self.components.push(component);
        }
    }
}

/// A module's name as a reader finds it: `harness::runner::frame (harness/src/runner/frame.rs)`.
pub fn module_name(krate: &str, m: &Module) -> String {
    let mut parts = vec![krate.to_string()];
    parts.extend(m.path.iter().cloned());
    format!("{} ({})", parts.join("::"), m.file.display())
}

/// A cycle in words: its modules, then per pair of modules on it the first import with file
/// and line (and how many more there are).
pub fn describe(krate: &str, ms: &[Module], c: &Cycle) -> String {
    let mut s = format!(
        "cycle in crate {krate} through {} modules:\n",
        c.modules.len()
    );
    for &m in &c.modules {
        s += &format!("  {}\n", module_name(krate, &ms[m]));
    }
    let mut shown: Vec<(usize, usize)> = Vec::new();
    for e in &c.edges {
        if shown.contains(&(e.from, e.to)) {
            continue;
        }
        shown.push((e.from, e.to));
        let more = c
            .edges
            .iter()
            .filter(|o| (o.from, o.to) == (e.from, e.to))
            .count()
            - 1;
        let path = |m: usize| ms[m].path.join("::");
        s += &format!(
            "    {} -> {}  ({}:{}: {}{})\n",
            path(e.from),
            path(e.to),
            ms[e.from].file.display(),
            e.line,
            e.what,
            if more > 0 {
                format!(", and {more} more")
            } else {
                String::new()
            }
        );
    }
    s
}
