"""Generated code only: written by `make generate`, never edited by hand."""
