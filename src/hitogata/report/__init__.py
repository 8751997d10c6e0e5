"""The reporting layer: tables, pictures and report folders over the computation's results.

It sits above the computation packages (body, skeleton, muscles, volume, fem,
elastic, dynamics, measure), which never import it nor the plotting
libraries it uses (matplotlib); every file it writes goes through
`hitogata.export.atomic`.

- `measurements`: `measurement_table` (the text table the CLI prints) and
  `measure_report` (a measurement report folder: JSON, CSV, pictures);
- `series`: a measurement series over time as CSV and a plot;
- `surface`: orthographic pictures of a body surface (front, back, side), drawn with numpy
  (`raster`, a depth buffer) and Pillow;
- `heatmap`: skin-strain heat maps on the posed body.
"""
