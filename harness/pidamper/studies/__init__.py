"""Studies: the resumable runner (`runner`: a table appended row by row, tasks on a process pool or
Dask), parametric studies over a grid (`study`) and the paper's figures (`paper`).  It may import the
running room, the inputs and the measures; the assessment borrows its runner."""
