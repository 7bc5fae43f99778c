"""What a run leaves: the Result and its files, the summary, numbers as text, other tools' CSV
dialects, comparisons, and the journals of study and fit folders."""
