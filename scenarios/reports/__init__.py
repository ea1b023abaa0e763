"""Reports: the paper reports (Markdown, HTML, figures), the Allan report, the README table, output folders."""
