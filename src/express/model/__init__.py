"""The model and its parameters: the records (bodies, connection points, elements, pins),
the live parameter graph with its units and ranges, substructures and the body classifier."""
