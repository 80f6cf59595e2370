//! The report page: one self-contained HTML file (styles inline, figures inline as SVG, no script,
//! nothing fetched), summary first, provenance next, then the sections.

use super::claim::{sig, Claim, Verdict};
use super::provenance::Provenance;
use super::{section_claims, Profile, SectionRun};

/// Escapes text for HTML.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

const STYLE: &str = "
body{font-family:'DejaVu Sans',Arial,sans-serif;margin:0 auto;max-width:1320px;padding:0 16px 40px;color:#222}
h1{margin:.6em 0 .2em}h2{margin-top:2em;border-bottom:2px solid #ccc;padding-bottom:4px}
table{border-collapse:collapse;margin:.6em 0;font-size:14px}
td,th{border:1px solid #ccc;padding:3px 8px;text-align:left;vertical-align:top}
th{background:#f0f0f0}td.num{text-align:right;font-variant-numeric:tabular-nums}
td.pass{background:#d9f2d9}td.fail{background:#f8d0d0;font-weight:bold}td.info{background:#e8eef8}
.banner{position:sticky;top:0;background:#fff3cd;border:1px solid #e0c060;padding:6px 10px;font-weight:bold;z-index:1}
.sectionbanner{color:#8a6d00;font-size:13px}
figure{margin:1em 0}figure svg{max-width:100%;height:auto;border:1px solid #eee}
figcaption{font-size:14px;color:#444}.note{font-size:13px;color:#555}
.counts span{margin-right:1.5em}
@media print{.banner{position:fixed;top:0;left:0;right:0}body{padding-top:40px}}
";

/// The whole page.
pub fn page(
    profile: Profile,
    prov: &Provenance,
    runs: &[SectionRun],
    svgs: &[Vec<String>],
) -> String {
    let mut h = String::new();
    h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
    h += &format!(
        "<title>cgdem validation report ({} profile)</title>\n<style>{STYLE}</style>\n</head>\n<body>\n",
        profile.name()
    );
    if !profile.banner().is_empty() {
        h += &format!(
            "<div class=\"banner\" id=\"profile-banner\">{}</div>\n",
            esc(profile.banner())
        );
    }
    h += &format!(
        "<h1>cgdem validation report</h1>\n<p>Profile <b>{}</b>. Every claim of the papers the \
         workbench reproduces on this branch, with its tolerance and verdict; data in \
         <code>summary.csv</code> and <code>figures/</code>.</p>\n",
        profile.name()
    );
    h += &summary(runs);
    h += &provenance(prov);
    let mut fig_no = 0;
    for (r, drawn) in runs.iter().zip(svgs) {
        h += &format!(
            "<section id=\"{}\">\n<h2>{}</h2>\n",
            esc(r.section.id),
            esc(r.section.title)
        );
        if !profile.banner().is_empty() {
            h += &format!("<p class=\"sectionbanner\">{}</p>\n", esc(profile.banner()));
        }
        h += &format!("<p class=\"note\">Wall time {} s.</p>\n", sig(r.seconds, 3));
        match &r.output {
            Err(e) => {
                h += &format!(
                    "<p class=\"fail\"><b>This section failed:</b> {}</p>\n",
                    esc(e)
                );
            }
            Ok(o) => {
                h += &o.html;
                for (f, svg) in o.figures.iter().zip(drawn) {
                    fig_no += 1;
                    h += &format!(
                        "<figure id=\"fig-{}\">\n{}\n<figcaption>Figure {fig_no}: {} Mirrors {}. \
                         Data: <code>figures/{}.csv</code> (also <code>.svg</code>, <code>.png</code>).\
                         </figcaption>\n</figure>\n",
                        esc(&f.name),
                        strip_xml_header(svg),
                        esc(&f.caption),
                        esc(&f.mirrors),
                        esc(&f.name)
                    );
                }
                if !o.claims.is_empty() {
                    h += &claims_table(&o.claims, None);
                }
            }
        }
        h += "</section>\n";
    }
    h += "</body>\n</html>\n";
    h
}

/// Standard base64 (RFC 4648, with padding), for images inlined in the page.
pub fn base64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(T[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// An `<img>` holding the PNG file at `path` inline (the page stays self-contained), or an error
/// naming the file.
pub fn png_img(path: &std::path::Path, alt: &str) -> crate::Result<String> {
    let png = std::fs::read(path).map_err(|e| crate::ValidationError::io(path, e))?;
    Ok(format!(
        "<img alt=\"{}\" style=\"max-width:100%\" src=\"data:image/png;base64,{}\">",
        esc(alt),
        base64(&png)
    ))
}

fn strip_xml_header(svg: &str) -> &str {
    svg.find("<svg").map_or(svg, |i| &svg[i..])
}

/// The summary: counts, then one row per claim of every section.
fn summary(runs: &[SectionRun]) -> String {
    let claims: Vec<(&str, Claim)> = runs
        .iter()
        .flat_map(|r| {
            section_claims(r)
                .into_iter()
                .map(move |c| (r.section.id, c))
        })
        .collect();
    let count = |v: Verdict| claims.iter().filter(|(_, c)| c.verdict() == v).count();
    let mut h = format!(
        "<h2 id=\"summary\">Summary</h2>\n<p class=\"counts\"><span>{} claims</span>\
         <span>pass {}</span><span>fail {}</span><span>info (not a target) {}</span></p>\n",
        claims.len(),
        count(Verdict::Pass),
        count(Verdict::Fail),
        count(Verdict::Info)
    );
    // The state at a glance: one row per section.
    h += "<table id=\"summary-sections\">\n<tr><th>section</th><th>pass</th><th>fail</th><th>info</th></tr>\n";
    for r in runs {
        let n = |v: Verdict| {
            claims
                .iter()
                .filter(|(s, c)| *s == r.section.id && c.verdict() == v)
                .count()
        };
        let fail = n(Verdict::Fail);
        h += &format!(
            "<tr><td><a href=\"#{}\">{}</a></td><td class=\"num\">{}</td><td class=\"num{}\">{fail}</td><td class=\"num\">{}</td></tr>\n",
            esc(r.section.id),
            esc(r.section.title),
            n(Verdict::Pass),
            if fail > 0 { " fail" } else { "" },
            n(Verdict::Info)
        );
    }
    h += "</table>\n";
    let owned: Vec<Claim> = claims.iter().map(|(_, c)| c.clone()).collect();
    let sections: Vec<&str> = claims.iter().map(|(s, _)| *s).collect();
    h += &claims_table(&owned, Some(&sections));
    h
}

fn claims_table(claims: &[Claim], sections: Option<&[&str]>) -> String {
    let id = if sections.is_some() {
        " id=\"summary-table\""
    } else {
        ""
    };
    let mut h = format!(
        "<table{id}>\n<tr><th>paper</th><th>item</th><th>quantity</th><th>reference</th>\
         <th>measured</th><th>tolerance</th><th>pass</th><th>note</th></tr>\n"
    );
    for (k, c) in claims.iter().enumerate() {
        let v = c.verdict();
        let item = match sections {
            Some(s) => format!("<a href=\"#{}\">{}</a>", esc(s[k]), esc(&c.item)),
            None => esc(&c.item),
        };
        h += &format!(
            "<tr><td>{}</td><td>{item}</td><td>{}</td><td class=\"num\">{}</td>\
             <td class=\"num\">{}</td><td>{}</td><td class=\"{}\">{}</td><td>{}</td></tr>\n",
            esc(&c.paper),
            esc(&c.quantity),
            sig(c.reference, 4),
            sig(c.measured, 4),
            esc(&c.tolerance.to_string()),
            v.name(),
            v.name(),
            esc(&c.note)
        );
    }
    h + "</table>\n"
}

fn provenance(p: &Provenance) -> String {
    let mut h = String::from("<h2 id=\"provenance\">Provenance</h2>\n<table>\n");
    for (k, v) in &p.rows {
        h += &format!("<tr><th>{}</th><td>{}</td></tr>\n", esc(k), esc(v));
    }
    h += "</table>\n<table>\n<tr><th>section</th><th>wall time (s)</th></tr>\n";
    for (k, s) in &p.timings {
        h += &format!(
            "<tr><td>{}</td><td class=\"num\">{}</td></tr>\n",
            esc(k),
            sig(*s, 3)
        );
    }
    h + "</table>\n"
}

#[cfg(test)]
mod tests {
    use super::esc;

    #[test]
    fn text_is_escaped() {
        assert_eq!(esc("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
    }
}
