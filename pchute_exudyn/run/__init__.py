"""A run: resolve it through the method table, integrate it phase by phase, name its samples as
columns, analyse and summarise it."""
