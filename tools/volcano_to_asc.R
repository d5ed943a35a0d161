#!/usr/bin/env Rscript
# Writes R's `volcano` data set (Maunga Whau, Auckland: 87 x 61 heights in metres on a 10 m grid,
# from r-base-core's datasets package) as an ESRI ASCII grid Talus (through GDAL) reads.
# In the data set, row i runs from south to north and column j from east to west (?volcano);
# an ESRI grid is written north-up, its first row the northernmost and its first column the
# westernmost, so cell (r, c) of the file is volcano[nrow - r, ncol - c] (r, c from 0).
# The data set carries no georeference: the grid's lower-left corner is put at (0, 0), local metres.
# Usage: Rscript tools/volcano_to_asc.R OUT.asc
args <- commandArgs(trailingOnly = TRUE)
if (length(args) != 1) stop("usage: Rscript tools/volcano_to_asc.R OUT.asc")
v <- datasets::volcano
grid <- v[nrow(v):1, ncol(v):1]  # north-up rows, west-to-east columns
out <- file(args[1], "w")
writeLines(c(sprintf("ncols %d", ncol(v)), sprintf("nrows %d", nrow(v)),
             "xllcorner 0", "yllcorner 0", "cellsize 10", "NODATA_value -9999"), out)
write.table(grid, out, row.names = FALSE, col.names = FALSE)
close(out)
