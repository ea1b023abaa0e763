"""Reports: the paper reports (Markdown, HTML, figures), the Allan report, the README summary and
the docs/results.md table, output folders."""
