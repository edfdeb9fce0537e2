from rotaflex.cli import main

main()
