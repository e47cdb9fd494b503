//! A small document model rendered both as Markdown and as a self-contained HTML page
//! (inline CSS, figures as inline SVG), so the two reports always say the same thing.

use std::fmt::Write;

/// One block of the report.
#[derive(Debug, Clone, PartialEq)]
pub enum Block {
    /// A heading of level 1–3.
    Heading(u8, String),
    /// A paragraph of plain text.
    Paragraph(String),
    /// A table: headers and rows of text cells.
    Table {
        /// Column headers.
        headers: Vec<String>,
        /// Rows, each as long as `headers`.
        rows: Vec<Vec<String>>,
    },
    /// A figure written as `figures/<name>.png` and `.svg`, with its caption.
    Figure {
        /// File stem under `figures/`.
        name: String,
        /// What was measured and how.
        caption: String,
        /// The SVG text, inlined in the HTML page.
        svg: String,
    },
}

/// The report as blocks.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Document {
    /// The blocks in order.
    pub blocks: Vec<Block>,
}

fn markdown_cell(text: &str) -> String {
    text.replace('|', "\\|").replace('\n', " ")
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Style of the HTML page: readable tables, figures scaled to the page width.
const STYLE: &str = "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;\
color:#222;line-height:1.45}table{border-collapse:collapse;margin:1em 0;font-size:0.9em}\
th,td{border:1px solid #bbb;padding:0.25em 0.6em;text-align:left}th{background:#eee}\
figure{margin:1.5em 0}figure svg{max-width:100%;height:auto}figcaption{font-size:0.9em;\
color:#444}.pass{color:#176d1f;font-weight:bold}.fail{color:#b3261e;font-weight:bold}";

impl Document {
    /// Appends a block.
    pub fn push(&mut self, block: Block) {
        self.blocks.push(block);
    }

    /// The Markdown text; figures link to `figures/<name>.png`.
    pub fn to_markdown(&self) -> String {
        let mut out = String::new();
        for block in &self.blocks {
            match block {
                Block::Heading(level, text) => {
                    let _ = writeln!(out, "{} {text}\n", "#".repeat(usize::from(*level)));
                }
                Block::Paragraph(text) => {
                    let _ = writeln!(out, "{text}\n");
                }
                Block::Table { headers, rows } => {
                    let cells = |r: &[String]| {
                        r.iter()
                            .map(|c| markdown_cell(c))
                            .collect::<Vec<_>>()
                            .join(" | ")
                    };
                    let _ = writeln!(out, "| {} |", cells(headers));
                    let _ = writeln!(out, "|{}|", vec!["---"; headers.len()].join("|"));
                    for row in rows {
                        let _ = writeln!(out, "| {} |", cells(row));
                    }
                    out.push('\n');
                }
                Block::Figure { name, caption, .. } => {
                    let _ = writeln!(
                        out,
                        "![{}](figures/{name}.png)\n\n*{}* ([SVG](figures/{name}.svg))\n",
                        markdown_cell(caption),
                        caption
                    );
                }
            }
        }
        out
    }

    /// A self-contained HTML page: inline CSS, figures inlined as SVG, no external file.
    pub fn to_html(&self, title: &str) -> String {
        let mut out = format!(
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
             <title>{}</title><style>{STYLE}</style></head><body>\n",
            escape(title)
        );
        for block in &self.blocks {
            match block {
                Block::Heading(level, text) => {
                    let _ = writeln!(out, "<h{level}>{}</h{level}>", escape(text));
                }
                Block::Paragraph(text) => {
                    let _ = writeln!(out, "<p>{}</p>", escape(text));
                }
                Block::Table { headers, rows } => {
                    out.push_str("<table><thead><tr>");
                    for h in headers {
                        let _ = write!(out, "<th>{}</th>", escape(h));
                    }
                    out.push_str("</tr></thead><tbody>\n");
                    for row in rows {
                        out.push_str("<tr>");
                        for cell in row {
                            let class = match cell.as_str() {
                                "pass" => " class=\"pass\"",
                                "FAIL" => " class=\"fail\"",
                                _ => "",
                            };
                            let _ = write!(out, "<td{class}>{}</td>", escape(cell));
                        }
                        out.push_str("</tr>\n");
                    }
                    out.push_str("</tbody></table>\n");
                }
                Block::Figure { caption, svg, .. } => {
                    // The XML declaration is not allowed inside HTML; the rest of the SVG
                    // document is valid inline.
                    let body = match svg.find("<svg") {
                        Some(i) => &svg[i..],
                        None => svg.as_str(),
                    };
                    let _ = writeln!(
                        out,
                        "<figure>{body}<figcaption>{}</figcaption></figure>",
                        escape(caption)
                    );
                }
            }
        }
        out.push_str("</body></html>\n");
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn html_escapes_text_and_inlines_svg_without_its_declaration() {
        let mut doc = Document::default();
        doc.push(Block::Paragraph("a < b & c".into()));
        doc.push(Block::Figure {
            name: "f".into(),
            caption: "cap".into(),
            svg: "<?xml version=\"1.0\"?><svg width=\"1\"></svg>".into(),
        });
        let html = doc.to_html("t");
        assert!(html.contains("a &lt; b &amp; c"));
        assert!(html.contains("<figure><svg width=\"1\"></svg>"));
        assert!(!html.contains("<?xml"));
    }
}
