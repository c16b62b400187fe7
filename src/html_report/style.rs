//! The report document's style sheet: screen and print (A4 portrait, 15 mm margins; tables and
//! figures never split across pages, headings kept with what follows).

pub const CSS: &str = r#"@page { size: A4 portrait; margin: 15mm 12mm; }
html { font-family: "DejaVu Sans", Arial, Helvetica, sans-serif; font-size: 10pt; color: #111; }
body { max-width: 186mm; margin: 0 auto; padding: 8px; }
h1 { font-size: 18pt; margin: 0 0 2pt 0; }
h2 { font-size: 13pt; margin: 14pt 0 6pt 0; border-bottom: 1px solid #999; break-after: avoid; page-break-after: avoid; }
p.sub { color: #444; margin: 0 0 8pt 0; }
p.note { font-size: 8.5pt; color: #333; }
table { border-collapse: collapse; margin: 4pt 0 10pt 0; font-size: 8pt; page-break-inside: avoid; break-inside: avoid; }
caption { text-align: left; font-weight: bold; font-size: 8.5pt; padding-bottom: 3pt; caption-side: top; }
th, td { border: 1px solid #bbb; padding: 1.5pt 4pt; }
th { background: #eee; font-weight: bold; text-align: center; }
td.n { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.pass { color: #15692b; font-weight: bold; }
td.fail { color: #b00020; font-weight: bold; }
tr { page-break-inside: avoid; break-inside: avoid; }
div.keep { page-break-inside: avoid; break-inside: avoid; }
div.row { display: flex; flex-wrap: wrap; gap: 10pt; align-items: flex-start; }
div.row figure { flex: 0 0 auto; }
figure { margin: 6pt 0 10pt 0; page-break-inside: avoid; break-inside: avoid; }
figure svg, figure img { max-width: 100%; height: auto; display: block; }
figcaption { font-size: 8.5pt; color: #333; margin-top: 3pt; }
dl.facts { display: grid; grid-template-columns: max-content auto; gap: 1pt 12pt; font-size: 9pt; page-break-inside: avoid; break-inside: avoid; }
dl.facts dt { font-weight: bold; }
dl.facts dd { margin: 0; }
footer { margin-top: 16pt; font-size: 8pt; color: #555; border-top: 1px solid #999; }
@media print { body { max-width: none; padding: 0; } section#views { page-break-before: always; } }
"#;
