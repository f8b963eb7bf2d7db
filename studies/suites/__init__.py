"""Record suites shipped with colonna (data: each a folder with its ``suite.toml``) and the
scripts that make them bit for bit (``make_*.py``)."""
