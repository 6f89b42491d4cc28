from rotleak.plot import main

main()
