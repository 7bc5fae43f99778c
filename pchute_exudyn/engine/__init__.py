"""The Exudyn layer: builds engine models from a Case and runs Exudyn's solvers. The only package importing exudyn."""
