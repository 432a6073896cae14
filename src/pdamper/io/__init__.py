"""Reading and writing: measured records, datasets, VTK. Knows no physics."""
