"""The paper's study reproduced: its published numbers (``reference``), the trims and Tables 3-4 and Figs. 9, 11,
13, 14 (``trims``), the stability studies of Figs. 15-19 (``studies``) and `hawksim reproduce` (``reproduce``)."""
