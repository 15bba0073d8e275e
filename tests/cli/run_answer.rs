//! `hemilab run`'s page leads with its answer: a first paragraph of at most three sentences that
//! names, as the answer, the configuration with the least MSE at equal time among those whose
//! error is not structured (advise's rule), and a structured one with less MSE only as rejected;
//! then the key figure; the method folded; the verdicts' family-wise level stated. Real binary, a
//! small sweep on the Cornell box whose static seed has structured error.

use crate::support::common::Tmp;
use hemilab::spec::Row;
use std::collections::HashMap;

fn spec() -> String {
    format!(
        r#"name = "answer"
scenes = ["{}"]
resolution = [32, 24]
replicates = 3
seed = 5
[reference]
rays = 512
replicates = 2
[[convergence]]
name = "sweep"
rays = [1, 2, 4, 8, 16]
rows = [
  {{ distribution = "sine-cosine", sequence = "random" }},
  {{ distribution = "sine-cosine", sequence = "fibonacci", seed_mode = "rotation" }},
  {{ distribution = "sine-cosine", sequence = "fibonacci", seed_mode = "static" }},
]
"#,
        crate::support::common::scene("cornell-box.toml")
    )
}

/// The text of the page's first `<p>`, and where it starts.
fn first_paragraph(html: &str) -> (usize, String) {
    let at = html.find("<p>").expect("a paragraph");
    let end = at + html[at..].find("</p>").expect("closed");
    (at, html[at + 3..end].replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">"))
}

/// Sentences: a full stop followed by a space or the end (decimal points are followed by digits).
fn sentences(p: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut start = 0;
    let chars: Vec<(usize, char)> = p.char_indices().collect();
    for (k, &(i, c)) in chars.iter().enumerate() {
        if c == '.' && chars.get(k + 1).is_none_or(|(_, n)| n.is_whitespace()) {
            out.push(p[start..=i].trim().to_string());
            start = i + 1;
        }
    }
    out
}

/// equal_time.csv's total-render-time lines as maps of column → value.
fn equal_time_lines(out: &std::path::Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(out.join("equal_time.csv")).expect("equal_time.csv");
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| header.iter().cloned().zip(l.split(',').map(String::from)).collect::<HashMap<_, _>>())
        .filter(|m| m["time"] == "total")
        .collect()
}

fn label(m: &HashMap<String, String>) -> String {
    Row::new(
        m["distribution"].parse().unwrap(),
        m["sequence"].parse().unwrap(),
        m["seed_mode"].parse().unwrap(),
    )
    .name()
}

#[test]
fn the_first_paragraph_is_the_answer_in_at_most_three_sentences_and_never_a_structured_estimator() {
    let dir = Tmp::new("answer");
    let spec = dir.spec("answer.toml", &spec());
    dir.run_ok(&spec, "out", "ref", &[]);
    let out = dir.path("out");
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    let (at, first) = first_paragraph(&html);
    assert!(
        at < html.find("<figure").unwrap() && at < html.find("<table").unwrap(),
        "the answer comes first"
    );
    let s = sentences(&first);
    assert!((1..=3).contains(&s.len()), "{} sentences: {s:#?}", s.len());

    let lines = equal_time_lines(&out);
    assert!(!lines.is_empty(), "the sweep is compared at equal time");
    for m in lines.iter().filter(|m| m["answer"] == "true") {
        assert_eq!(m["structured"], "false", "an answer with structured error: {m:?}");
    }
    // The static seed's error is structured here, so the rule is exercised.
    let static_lines: Vec<_> = lines.iter().filter(|m| m["seed_mode"] == "static").collect();
    assert!(static_lines.iter().all(|m| m["structured"] == "true"), "{static_lines:?}");
    // The answer sentence names the configuration that is the answer at most budgets, and none
    // whose error is structured at every budget.
    let mut answers: Vec<(String, usize)> = Vec::new();
    for m in lines.iter().filter(|m| m["answer"] == "true") {
        match answers.iter_mut().find(|(l, _)| *l == label(m)) {
            Some((_, n)) => *n += 1,
            None => answers.push((label(m), 1)),
        }
    }
    // The most budgets, and of equals the first in budget order (the page's order).
    let most = answers.iter().map(|(_, n)| *n).max().expect("an answer");
    let top = &answers.iter().find(|(_, n)| *n == most).unwrap().0;
    assert!(s[0].contains(&format!("is {top}")), "'{top}' is not the answer sentence's: {}", s[0]);
    let static_label = label(static_lines[0]);
    assert!(!s[0].contains(&static_label), "the answer sentence names the structured estimator: {}", s[0]);
    // Where the structured estimator has the least MSE, the paragraph rejects it by name.
    if static_lines.iter().any(|m| m["rank"] == "1") {
        let rejected = s.iter().find(|x| x.contains("rejected")).unwrap_or_else(|| panic!("{first}"));
        assert!(
            rejected.to_lowercase().contains(&static_label.to_lowercase()) && rejected.contains("structured"),
            "{rejected}"
        );
    }

    // The key figure comes right after the answer; the method is folded; Holm's level is stated.
    let figure = html.find("<figure").unwrap();
    assert!(
        html[figure..].starts_with("<figure>\n<a href=\"sweep_equal_time.png\">"),
        "{}",
        &html[figure..figure + 80]
    );
    let method = html.find(hemilab::report::METHOD_SUMMARY).expect("the method, folded");
    assert!(html[..method].ends_with("<summary><h2 style=\"display:inline\">"));
    assert!(html.find(hemilab::timing::TIME_INCLUDES).unwrap() > method, "the timing text is in the method");
    assert!(!html.contains(" z +") && !html.contains("(z "), "paired statistics are t, not z");
}
