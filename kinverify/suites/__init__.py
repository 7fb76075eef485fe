"""Property suites: the contract (:mod:`.base`), one module per suite, and the registry
(:mod:`.registry`) that lists them in report order."""
