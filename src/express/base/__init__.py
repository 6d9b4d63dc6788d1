"""Base pieces every stage uses: problems and error types, the restricted expression grammar,
units, limits of input sizes and thread settings. Imports nothing else of the package."""
