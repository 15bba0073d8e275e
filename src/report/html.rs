//! One offline page with every figure and the results table, as HTML and as Markdown. Figures are
//! referenced by relative path (the page lives beside them), so the output directory can be moved
//! or zipped and still read; nothing is fetched from the network.

/// A figure file (relative to the page) with its caption and optional extra files linked below
/// it (e.g. the SVG version of a PNG).
pub struct Figure {
    pub path: String,
    pub caption: String,
    pub links: Vec<String>,
}

/// A results table: header and rows of already formatted cells.
pub struct Table {
    pub title: String,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

const STYLE: &str = "body{font-family:sans-serif;max-width:1400px;margin:2em auto;padding:0 1em;color:#222}\
table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #bbb;padding:.3em .6em;text-align:right}\
th{background:#eee}td:first-child,th:first-child{text-align:left}\
figure{margin:2em 0}img{max-width:100%;border:1px solid #ddd}figcaption{margin-top:.4em}";

/// One page: the title, `lead` tables right under it (what a reader must see first), intro
/// paragraphs (plain text, blank line = new paragraph), an `interactive` section, tables, figures,
/// then `collapsed` tables, each folded in a `<details>` element (long reference tables that would
/// otherwise push the figures off the first screens).
pub struct Page<'a> {
    pub title: &'a str,
    pub lead: &'a [Table],
    pub intro: &'a str,
    /// HTML the page's owner made whole (the comparison viewer, `report::viewer`), put in as it is
    /// after the intro and the method; empty for none. The Markdown page points to the HTML one.
    pub interactive: &'a str,
    pub tables: &'a [Table],
    pub figures: &'a [Figure],
    pub collapsed: &'a [Table],
}

/// What opens a page before its lead tables, for a page that leads with its answer: the answer
/// (paragraphs, plain text), the figures that show it, and the method text, folded in a
/// `<details>` element after the lead tables and the page's intro — a reader who wants the answer
/// should not scroll past how it was found. Empty parts are left out, so the default is no opening.
#[derive(Default)]
pub struct Opening<'a> {
    pub answer: &'a str,
    pub figures: &'a [Figure],
    pub method: &'a str,
}

/// The summary line of the folded method text.
pub const METHOD_SUMMARY: &str = "Method: how the numbers were measured and compared";

fn paragraphs(text: &str) -> impl Iterator<Item = &str> {
    text.split("\n\n").map(str::trim).filter(|p| !p.is_empty())
}

/// The page as HTML.
pub fn html_page(page: &Page) -> String {
    html_page_opened(page, &Opening::default())
}

/// The page as HTML, opened by `opening`: title, answer, key figures, lead tables, intro, the
/// method folded, tables, figures, folded tables.
pub fn html_page_opened(page: &Page, opening: &Opening) -> String {
    let Page { title, lead, intro, interactive, tables, figures, collapsed } = *page;
    let mut s = String::new();
    s += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
    s += &format!("<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n", esc(title));
    s += &format!("<h1>{}</h1>\n", esc(title));
    for p in paragraphs(opening.answer) {
        s += &format!("<p>{}</p>\n", esc(p));
    }
    opening.figures.iter().for_each(|f| s += &html_figure(f));
    for t in lead {
        s += &format!("<h2>{}</h2>\n", esc(&t.title));
        s += &html_table(t);
    }
    for p in paragraphs(intro) {
        s += &format!("<p>{}</p>\n", esc(p));
    }
    if !opening.method.trim().is_empty() {
        s += &format!(
            "<details>\n<summary><h2 style=\"display:inline\">{}</h2></summary>\n",
            esc(METHOD_SUMMARY)
        );
        for p in paragraphs(opening.method) {
            s += &format!("<p>{}</p>\n", esc(p));
        }
        s += "</details>\n";
    }
    s += interactive;
    for t in tables {
        s += &format!("<h2>{}</h2>\n", esc(&t.title));
        s += &html_table(t);
    }
    figures.iter().for_each(|f| s += &html_figure(f));
    for t in collapsed {
        s += &format!("<details>\n<summary><h2 style=\"display:inline\">{}</h2></summary>\n", esc(&t.title));
        s += &html_table(t);
        s += "</details>\n";
    }
    s += "</body>\n</html>\n";
    s
}

fn html_figure(f: &Figure) -> String {
    let mut s = format!(
        "<figure>\n<a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a>\n<figcaption>{1}",
        esc(&f.path),
        esc(&f.caption)
    );
    for l in &f.links {
        s += &format!(" <a href=\"{0}\">[{0}]</a>", esc(l));
    }
    s + "</figcaption>\n</figure>\n"
}

fn html_table(t: &Table) -> String {
    let mut s = String::from("<table>\n<tr>");
    for h in &t.header {
        s += &format!("<th>{}</th>", esc(h));
    }
    s += "</tr>\n";
    for row in &t.rows {
        s += "<tr>";
        for c in row {
            s += &format!("<td>{}</td>", esc(c));
        }
        s += "</tr>\n";
    }
    s += "</table>\n";
    s
}

/// The same page as Markdown (renders on GitHub and in any Markdown viewer; GitHub folds the
/// `<details>`).
pub fn markdown_page(page: &Page) -> String {
    markdown_page_opened(page, &Opening::default())
}

/// `html_page_opened` as Markdown.
pub fn markdown_page_opened(page: &Page, opening: &Opening) -> String {
    let Page { title, lead, intro, interactive, tables, figures, collapsed } = *page;
    let md_table = markdown_table;
    let md_figure = |f: &Figure| {
        let mut s =
            format!("![{}]({})\n\n{}", f.caption.replace(['[', ']'], ""), md_path(&f.path), f.caption);
        for l in &f.links {
            s += &format!(" [{l}]({})", md_path(l));
        }
        s + "\n\n"
    };
    let mut s = format!("# {title}\n\n");
    for p in paragraphs(opening.answer) {
        s += &format!("{p}\n\n");
    }
    opening.figures.iter().for_each(|f| s += &md_figure(f));
    for t in lead {
        s += &format!("## {}\n\n{}\n", t.title, md_table(t));
    }
    for p in paragraphs(intro) {
        s += &format!("{p}\n\n");
    }
    if !opening.method.trim().is_empty() {
        s += &format!("<details>\n<summary>{METHOD_SUMMARY}</summary>\n\n");
        for p in paragraphs(opening.method) {
            s += &format!("{p}\n\n");
        }
        s += "</details>\n\n";
    }
    if !interactive.is_empty() {
        s += "The images can be compared side by side, zoomed and stepped through their frames in the \
              viewer of the HTML page (index.html, section \"Compare the images\").\n\n";
    }
    for t in tables {
        s += &format!("## {}\n\n", t.title);
        s += &md_table(t);
        s += "\n";
    }
    figures.iter().for_each(|f| s += &md_figure(f));
    for t in collapsed {
        s += &format!("<details>\n<summary>{}</summary>\n\n{}\n</details>\n\n", t.title, md_table(t));
    }
    s
}

/// A table as Markdown (header, rule, rows; `|` in a cell escaped), without its title.
pub fn markdown_table(t: &Table) -> String {
    let cell = |c: &str| c.replace('|', "\\|").replace('\n', " ");
    let mut s = format!("| {} |\n", t.header.iter().map(|h| cell(h)).collect::<Vec<_>>().join(" | "));
    s += &format!("|{}\n", "---|".repeat(t.header.len().max(1)));
    for row in &t.rows {
        s += &format!("| {} |\n", row.iter().map(|c| cell(c)).collect::<Vec<_>>().join(" | "));
    }
    s
}

/// Every local file an HTML page links to or embeds (`src` and `href` attributes, excluding web,
/// mail and in-page links), without duplicates. Lets a test (or the
/// app) check that a page references only files that exist.
pub fn referenced_files(html: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for attr in ["src=\"", "href=\""] {
        let mut rest = html;
        while let Some(i) = rest.find(attr) {
            rest = &rest[i + attr.len()..];
            let Some(end) = rest.find('"') else { break };
            let target = unesc(&rest[..end]);
            let remote = ["http:", "https:", "mailto:", "data:", "#"].iter().any(|p| target.starts_with(p));
            if !remote && !target.is_empty() && !out.contains(&target) {
                out.push(target);
            }
        }
    }
    out
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn unesc(s: &str) -> String {
    s.replace("&quot;", "\"").replace("&gt;", ">").replace("&lt;", "<").replace("&amp;", "&")
}

/// Markdown link targets with spaces or parentheses need angle brackets.
fn md_path(p: &str) -> String {
    if p.contains([' ', '(', ')']) { format!("<{p}>") } else { p.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figures() -> Vec<Figure> {
        vec![
            Figure { path: "table2.png".into(), caption: "Table 2 <AO>".into(), links: vec![] },
            Figure {
                path: "convergence_rays.png".into(),
                caption: "RMSE & rays".into(),
                links: vec!["convergence_rays.svg".into()],
            },
        ]
    }

    fn table() -> Table {
        Table {
            title: "RMSE".into(),
            header: vec!["configuration".into(), "8".into()],
            rows: vec![vec!["random | sine-cosine".into(), "0.0512".into()]],
        }
    }

    fn page<'a>(title: &'a str, intro: &'a str, tables: &'a [Table], figures: &'a [Figure]) -> Page<'a> {
        Page { title, lead: &[], intro, interactive: "", tables, figures, collapsed: &[] }
    }

    #[test]
    fn html_references_exactly_the_given_files() {
        let (t, f) = ([table()], figures());
        let html = html_page(&page("Paper", "Intro.\n\nSecond <b>para</b>.", &t, &f));
        let mut files = referenced_files(&html);
        files.sort();
        assert_eq!(files, ["convergence_rays.png", "convergence_rays.svg", "table2.png"]);
        assert!(html.contains("Table 2 &lt;AO&gt;") && html.contains("RMSE &amp; rays"), "text is escaped");
        assert!(html.contains("Second &lt;b&gt;para&lt;/b&gt;.") && !html.contains("<b>"));
        assert!(html.contains("<td>0.0512</td>"));
        assert!(referenced_files(&html_page(&page("t", "", &[], &[]))).is_empty());
    }

    #[test]
    fn referenced_files_skips_web_links_and_unescapes() {
        let html = r##"<a href="https://x.org">x</a><a href="#top">t</a><img src="a&amp;b.png"><img src="a&amp;b.png">"##;
        assert_eq!(referenced_files(html), ["a&b.png"]);
    }

    #[test]
    fn markdown_has_the_table_and_every_figure() {
        let (t, f) = ([table()], figures());
        let md = markdown_page(&page("Paper", "Intro.", &t, &f));
        assert!(md.starts_with("# Paper\n"));
        assert!(md.contains("| configuration | 8 |\n|---|---|\n| random \\| sine-cosine | 0.0512 |"), "{md}");
        assert!(md.contains("![Table 2 <AO>](table2.png)"));
        assert!(md.contains("[convergence_rays.svg](convergence_rays.svg)"));
    }

    /// An opening puts the answer and its figure first, and folds the method after the intro.
    #[test]
    fn an_opening_leads_with_the_answer_and_folds_the_method() {
        let (lead, f) = ([table()], figures());
        let p = Page { lead: &lead, ..page("Paper", "Findings.", &[], &f[1..]) };
        let o = Opening { answer: "The answer.\n\nAnother scene's.", figures: &f[..1], method: "How." };
        let (html, md) = (html_page_opened(&p, &o), markdown_page_opened(&p, &o));
        let at = |s: &str, x: &str| s.find(x).unwrap_or_else(|| panic!("{x} missing:\n{s}"));
        assert!(at(&html, "<p>The answer.</p>") < at(&html, "table2.png"));
        assert!(at(&html, "table2.png") < at(&html, "<td>0.0512</td>"));
        assert!(at(&html, "<p>Findings.</p>") < at(&html, "<details>"));
        assert!(at(&html, "<details>") < at(&html, "<p>How.</p>"));
        assert!(
            html.find("<p>").unwrap() == at(&html, "<p>The answer.</p>"),
            "the answer is the first paragraph"
        );
        assert!(at(&md, "The answer.") < at(&md, "](table2.png)") && at(&md, "Findings.") < at(&md, "How."));
        assert_eq!(
            html_page(&p),
            html_page_opened(&p, &Opening::default()),
            "no opening: the page as before"
        );
    }

    /// Lead tables come right under the title, before the intro.
    #[test]
    fn lead_tables_open_the_page() {
        let (lead, f) = ([table()], figures());
        let p = Page { lead: &lead, ..page("Paper", "Intro.", &[], &f) };
        let (html, md) = (html_page(&p), markdown_page(&p));
        assert!(html.find("<td>0.0512</td>").unwrap() < html.find("<p>Intro.</p>").unwrap());
        assert!(md.find("| configuration |").unwrap() < md.find("Intro.").unwrap());
    }
}
