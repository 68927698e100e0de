//! Checks of a STEP file's references before OpenCASCADE parses it: a
//! reference to an instance the file does not define, and a cycle of
//! `ORIENTED_EDGE` references (an oriented edge whose edge element is, through
//! other oriented edges, itself). On either, OCCT's parser (7.6) recurses
//! through oriented edges while it builds its entity graph until the stack
//! overflows — a crash no signal handler can turn into an error — so the file
//! is refused first. The fuzzer (`crates/fuzz`) found both with one damaged
//! line.

use std::collections::{HashMap, HashSet};

/// Why the file's references cannot be parsed safely, or `None`.
pub(crate) fn reference_error(text: &[u8]) -> Option<String> {
    if let Some(r) = undefined_reference(text) {
        return Some(format!("it refers to #{r}, which it does not define"));
    }
    oriented_edge_cycle(text)
        .map(|at| format!("ORIENTED_EDGE {at} refers, through oriented edges, to itself"))
}

/// The lowest instance referred to (`#N` on the right of `=`, outside
/// strings) but never defined (`#N =` at the start of a statement).
fn undefined_reference(text: &[u8]) -> Option<u64> {
    let mut defined = HashSet::new();
    let mut used = Vec::new();
    for (id, rhs) in instances(text) {
        defined.insert(id);
        let mut quoted = false;
        let mut i = 0;
        while i < rhs.len() {
            match rhs[i] {
                b'\'' => quoted = !quoted,
                b'#' if !quoted => {
                    let n = rhs[i + 1..]
                        .iter()
                        .take_while(|b| b.is_ascii_digit())
                        .count();
                    if let Some(r) = number(&rhs[i + 1..i + 1 + n]) {
                        used.push(r);
                    }
                    i += n;
                }
                _ => {}
            }
            i += 1;
        }
    }
    used.into_iter().filter(|r| !defined.contains(r)).min()
}

/// The value of a run of ASCII digits.
fn number(digits: &[u8]) -> Option<u64> {
    std::str::from_utf8(digits).ok()?.parse().ok()
}

/// The first oriented edge on a cycle of `ORIENTED_EDGE` references, as its
/// instance name (`#12`), or `None`.
fn oriented_edge_cycle(text: &[u8]) -> Option<String> {
    let element = oriented_edge_elements(text);
    // 0: not seen, 1: on the current chain, 2: done
    let mut state: HashMap<u64, u8> = HashMap::new();
    let mut ids: Vec<u64> = element.keys().copied().collect();
    ids.sort_unstable();
    for &start in &ids {
        let mut chain = Vec::new();
        let mut at = start;
        loop {
            match state.get(&at).copied().unwrap_or(0) {
                1 => return Some(format!("#{at}")),
                2 => break,
                _ => {}
            }
            state.insert(at, 1);
            chain.push(at);
            match element.get(&at) {
                Some(&next) => at = next,
                None => break,
            }
        }
        for v in chain {
            state.insert(v, 2);
        }
    }
    None
}

/// `#id → #element` of every `ORIENTED_EDGE` instance (its fourth argument,
/// when that is a reference).
fn oriented_edge_elements(text: &[u8]) -> HashMap<u64, u64> {
    let mut out = HashMap::new();
    for (id, rhs) in instances(text) {
        let Some(args) = rhs.trim_ascii().strip_prefix(b"ORIENTED_EDGE") else {
            continue;
        };
        let Some(args) = args.trim_ascii().strip_prefix(b"(") else {
            continue;
        };
        if let Some(r) = top_level_args(args).get(3).and_then(|a| reference(a)) {
            out.insert(id, r);
        }
    }
    out
}

/// The instances of the text: `#id = rhs` statements as `(id, rhs)`.
fn instances(text: &[u8]) -> impl Iterator<Item = (u64, &[u8])> {
    statements(text).into_iter().filter_map(|statement| {
        let rest = statement.trim_ascii().strip_prefix(b"#")?;
        let digits = rest.iter().take_while(|b| b.is_ascii_digit()).count();
        let id = number(&rest[..digits])?;
        let rhs = rest[digits..].trim_ascii().strip_prefix(b"=")?;
        Some((id, rhs))
    })
}

/// The statements of the text, split at `;` outside quoted strings.
fn statements(text: &[u8]) -> Vec<&[u8]> {
    let mut out = Vec::new();
    let (mut start, mut quoted) = (0, false);
    for (i, &b) in text.iter().enumerate() {
        match b {
            b'\'' => quoted = !quoted,
            b';' if !quoted => {
                out.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out
}

/// The arguments of a parameter list (after its opening parenthesis), split
/// at top-level commas.
fn top_level_args(list: &[u8]) -> Vec<&[u8]> {
    let mut out = Vec::new();
    let (mut depth, mut quoted, mut start) = (0i32, false, 0);
    for (i, &b) in list.iter().enumerate() {
        match b {
            b'\'' => quoted = !quoted,
            b'(' if !quoted => depth += 1,
            b')' if !quoted => {
                if depth == 0 {
                    out.push(&list[start..i]);
                    return out;
                }
                depth -= 1;
            }
            b',' if !quoted && depth == 0 => {
                out.push(&list[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&list[start..]);
    out
}

/// The instance number of a `#N` argument.
fn reference(arg: &[u8]) -> Option<u64> {
    std::str::from_utf8(arg.trim_ascii().strip_prefix(b"#")?)
        .ok()?
        .parse()
        .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cycle_of_oriented_edges_is_found() {
        let good = b"DATA;\n#1=EDGE_CURVE('',#5,#6,#7,.T.);\n#2=ORIENTED_EDGE('',*,*,#1,.T.);\n#3=ORIENTED_EDGE('a;b',*,*,#2,.F.);\nENDSEC;";
        assert_eq!(oriented_edge_cycle(good), None);
        assert_eq!(
            oriented_edge_elements(good),
            HashMap::from([(2, 1), (3, 2)])
        );
        let selfref = b"#4 = ORIENTED_EDGE ( '', *, *, #4, .T. ) ;";
        assert_eq!(oriented_edge_cycle(selfref).as_deref(), Some("#4"));
        let pair = b"#2=ORIENTED_EDGE('',*,*,#3,.T.);#3=ORIENTED_EDGE('(x,',*,*,#2,.T.);#9=ORIENTED_EDGE('',*,*,#2,.T.);";
        assert_eq!(oriented_edge_cycle(pair).as_deref(), Some("#2"));
        assert!(reference_error(pair).unwrap().contains("#2 refers"));
    }

    #[test]
    fn an_undefined_reference_is_found() {
        let ok = b"#1=CARTESIAN_POINT('#7',(0.,0.,0.));#2=VERTEX_POINT('',#1);";
        assert_eq!(undefined_reference(ok), None);
        assert_eq!(reference_error(ok), None);
        let bad = b"#2=VERTEX_POINT('',#1);#3=EDGE_CURVE('',#2,#12,#9,.T.);";
        assert_eq!(undefined_reference(bad), Some(1));
        assert_eq!(
            reference_error(bad).unwrap(),
            "it refers to #1, which it does not define"
        );
    }
}
