"""The shipped scenes (TOML), installed with the package as pidamper.scenes."""
