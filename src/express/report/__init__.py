"""The HTML report of a model (``express report``): :mod:`.page` owns the page format
(inline SVG, MathML, no network), :mod:`.build` the sections."""
