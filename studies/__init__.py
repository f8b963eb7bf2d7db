"""colonna.studies: the command line, declarative studies and their reports."""
