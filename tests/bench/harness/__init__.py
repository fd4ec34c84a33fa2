"""scripts/bench: runs porter-plan over the paper's tables, validates every result with
porter-validate, and writes results.json and docs/benchmarks.md with plots."""
