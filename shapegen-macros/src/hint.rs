//! "Did you mean" hints: the closest of the words a position accepts.

/// The candidate closest to `word` by edit distance, if it is close enough to
/// be a likely misspelling (at most one edit per three letters, at least one).
pub fn closest<S: AsRef<str>>(
    word: &str,
    candidates: impl IntoIterator<Item = S>,
) -> Option<String> {
    let limit = (word.chars().count() / 3).max(1);
    candidates
        .into_iter()
        .map(|c| {
            let c = c.as_ref().to_owned();
            (distance(&word.to_lowercase(), &c.to_lowercase()), c)
        })
        .filter(|(d, c)| {
            let (w, lower) = (word.to_lowercase(), c.to_lowercase());
            // A near miss, or a longer or shorter form (`parameters`, `param`):
            // all but the last letter of the shorter word in common.
            let common = w
                .chars()
                .zip(lower.chars())
                .take_while(|(a, b)| a == b)
                .count();
            let prefix = common >= 4 && common + 1 >= w.len().min(lower.len());
            (*d <= limit || prefix) && c != word
        })
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// `head`, then what the position accepts (`tail`), with a hint between
/// them if one candidate is close: "unknown section `slot`: did you mean
/// `slots`? A node holds ...".
pub fn message<S: AsRef<str>>(
    head: &str,
    word: &str,
    candidates: impl IntoIterator<Item = S>,
    tail: &str,
) -> String {
    match closest(word, candidates) {
        Some(c) => {
            let mut t = tail.chars();
            let tail: String = t
                .next()
                .map_or_else(String::new, |f| f.to_uppercase().chain(t).collect());
            format!("{head}: did you mean `{c}`? {tail}")
        }
        None => format!("{head}; {tail}"),
    }
}

/// `": did you mean `x`?"` for the closest candidate, or nothing.
pub fn did_you_mean<S: AsRef<str>>(word: &str, candidates: impl IntoIterator<Item = S>) -> String {
    closest(word, candidates).map_or_else(String::new, |c| format!(": did you mean `{c}`?"))
}

/// Levenshtein distance (insertions, deletions, substitutions; transpositions count 2).
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let substitution = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substitution.min(row[j] + 1).min(diagonal + 1);
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_misses_get_a_hint_and_others_none() {
        let keywords = ["params", "slots", "consts"];
        let closest = |w, c: &[&str]| super::closest(w, c.iter().copied());
        let keywords = &keywords[..];
        assert_eq!(closest("slot", keywords).as_deref(), Some("slots"));
        assert_eq!(closest("param", keywords).as_deref(), Some("params"));
        assert_eq!(closest("Slots", keywords).as_deref(), Some("slots"));
        assert_eq!(closest("children", keywords), None);
        assert_eq!(closest("parameters", keywords).as_deref(), Some("params"));
        assert_eq!(closest("slots", keywords), None);
        assert_eq!(closest("emit", &["emits"]).as_deref(), Some("emits"));
        assert_eq!(
            closest("unifrom", &["uniform", "normal"]).as_deref(),
            Some("uniform")
        );
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("", "abc"), 3);
    }
}
