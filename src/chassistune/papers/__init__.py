"""The four papers of the first release: their published numbers and their reproductions."""
