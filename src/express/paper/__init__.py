"""The paper (Tanifuji & Suzuki, 2001): its published numbers and the demo that re-creates
its figures with computed verdicts, running every stage including the exports."""
