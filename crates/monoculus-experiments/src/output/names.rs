//! Names for a list of outputs that stay distinct whatever labels they are made from.

use std::collections::HashMap;

/// A file stem per label, in safe characters (ASCII letters, digits, `-`, `.`, others
/// as `_`), made distinct: a stem two labels would share (labels that differ only in
/// characters outside that set, or in case, which some file systems ignore) gives way to
/// `<fallback>_<index>` for every label that has it. The result has one stem per label,
/// no two equal, ignoring case.
///
/// ```
/// use monoculus_experiments::output::unique_stems;
///
/// let stems = unique_stems(&["run_n=10", "run_é.csv", "run_ü.csv"], "run_cell");
/// assert_eq!(stems, ["run_n_10", "run_cell1", "run_cell2"]);
/// ```
pub fn unique_stems<S: AsRef<str>>(labels: &[S], fallback: &str) -> Vec<String> {
    let safe: Vec<String> = labels
        .iter()
        .map(|l| {
            l.as_ref()
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                        c
                    } else {
                        '_'
                    }
                })
                .collect()
        })
        .collect();
    let mut count: HashMap<String, usize> = HashMap::new();
    for s in &safe {
        *count.entry(s.to_ascii_lowercase()).or_default() += 1;
    }
    let mut stems: Vec<String> = safe
        .into_iter()
        .enumerate()
        .map(|(k, s)| {
            if count[&s.to_ascii_lowercase()] > 1 {
                format!("{fallback}{k}")
            } else {
                s
            }
        })
        .collect();
    // A fallback can itself collide with a label's stem (a label `run_cell1`): number
    // every stem then.
    let mut seen = std::collections::HashSet::new();
    if !stems.iter().all(|s| seen.insert(s.to_ascii_lowercase())) {
        stems = (0..labels.len())
            .map(|k| format!("{fallback}{k}"))
            .collect();
    }
    stems
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stems_are_distinct_whatever_the_labels() {
        assert_eq!(unique_stems(&["a", "b"], "x"), ["a", "b"]);
        assert_eq!(unique_stems(&["Run", "run"], "x_"), ["x_0", "x_1"]);
        assert_eq!(
            unique_stems(&["x_1", "é", "ü"], "x_"),
            ["x_0", "x_1", "x_2"]
        );
        let many: Vec<String> = (0..300)
            .map(|k| format!("{}", (b'a' + (k % 3) as u8) as char))
            .collect();
        let stems = unique_stems(&many, "c");
        let set: std::collections::HashSet<_> = stems.iter().collect();
        assert_eq!(set.len(), 300);
    }
}
